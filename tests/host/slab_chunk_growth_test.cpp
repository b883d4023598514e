// The room for the output a slab worker keeps for its turn (pipeline/slab_write_turns.h): a
// worker ahead of the writer takes more chunks rather than wait for its turn, up to its most
// (most_chunks_per_worker): large slices make slabs whose output does not fit the first four,
// and workers that wait take turns instead of working side by side. What the grown chunks hold
// is written as any other: the file is one thread's, byte for byte.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <future>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "memory_slab_slices.h"
#include "mvox/engine.h"
#include "pipeline/blocking_queue.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_engine_run.h"
#include "pipeline/slab_extraction.h"
#include "pipeline/slab_write_turns.h"
#include "read/memory/memory_volume_source.h"
#include "slab_run_checks.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {
namespace {

// Worker 1 extracts slab 1 while the turn is at slab 0: every chunk it takes holds output that
// cannot be written yet. It gets `most` chunks at once; the next one waits for the turn (here:
// for the run to be cancelled). The worker runs on a thread of its own, so that a build that
// makes it wait too early fails here rather than hangs.
void expect_chunks_before_waiting(unsigned most) {
  Cancellation cancellation;
  SlabWriteTurns turns(
      nullptr, 4, 2, EngineOptions(), cancellation, [] {}, most);
  turns.start_slab(1, 1);
  SlabRecorder::Handover& handover = turns.handover(1);
  std::atomic<unsigned> taken{0};
  std::set<SlabChunk*> chunks;
  SlabChunk* last = nullptr;
  std::thread worker([&] {
    for (;;) {
      last = handover.take();
      if (!last) return;
      chunks.insert(last);
      ++taken;
    }
  });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (taken.load() < most && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  // Still waiting for chunk most + 1 a moment later: its turn never comes. (A check that looks
  // too early passes without proving anything, but cannot fail a correct build.)
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const unsigned before_cancel = taken.load();
  cancellation.cancel();
  turns.wake();
  worker.join();
  EXPECT_EQ(before_cancel, most) << "chunks taken before the turn came, of at most " << most;
  EXPECT_EQ(chunks.size(), taken.load());  // every one a chunk of its own
  EXPECT_EQ(last, nullptr);
}

TEST(SlabChunkGrowth, AWorkerAheadTakesChunksUpToItsMostThenWaitsForItsTurn) {
  expect_chunks_before_waiting(kChunksPerWorker);
  expect_chunks_before_waiting(11);
}

TEST(SlabChunkGrowth, AWorkerMayHoldAboutOneByteOfOutputPerVoxelOfItsSlabAndAtLeastSixChunks) {
  VolumeInfo info;
  info.type = SampleType::u8;
  info.width = 256;
  info.height = 256;
  info.depth = 1024;
  // The paper's engine at this size emits about 1.2 MB a slab of 16 slices: a worker ahead of
  // one writing a file still needs more than the four it starts with, for that slab and most
  // of its next.
  EXPECT_GT(kFewestMostChunks, kChunksPerWorker);
  EXPECT_EQ(most_chunks_per_worker(info, 16), kFewestMostChunks);
  info.width = info.height = 1024;
  EXPECT_EQ(most_chunks_per_worker(info, 8), 16u);  // 8 Mi voxels: 16 chunks of 512 KiB
  info.width = info.height = 2048;
  EXPECT_EQ(most_chunks_per_worker(info, 8), 64u);
}

// Two slabs of noise. Worker 1 extracts slab 1 first, on a thread of its own: its turn cannot
// come before slab 0 is written, so all its output goes into chunks, more than four (without
// growing it would wait for ever; the test gives up after 20 s). Then worker 0 extracts slab 0,
// writing straight, and worker 1 writes what it recorded: the file is one engine's.
TEST(SlabChunkGrowth, ASlabRecordedInMoreThanFourChunksIsWrittenAsOneEngineWritesIt) {
  const VolumeInfo info = test::u8_volume(128, 128, 16);
  const auto samples = test::noise_samples(info, 3);
  test::ScratchDirectory dir;
  const EngineOptions engine;
  {
    MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                              info.width);
    const auto writer = open_mesh_writer(dir.file("one.ply"), MeshFormat::ply, {});
    ASSERT_EQ(run_pipeline(source, 128, engine, *writer, "noise").status, Status::ok);
    writer->finish();
  }
  const auto writer = open_mesh_writer(dir.file("slabs.ply"), MeshFormat::ply, {});
  Cancellation cancellation;
  SlabWriteTurns turns(
      writer.get(), 2, 2, engine, cancellation, [] {}, kMostChunks);
  test::MemorySlabSlices slices(samples, info);
  const std::size_t workspace_bytes = engine_workspace_bytes(info.width, info.height, engine);
  auto extract = [&](unsigned worker) {
    std::vector<std::uint64_t> workspace(workspace_bytes / 8 + 1);
    SlabRecorder recorder(turns.handover(worker), &writer->placement(), nullptr, false);
    turns.start_slab(worker, worker);
    const SlabSpan span = SlabSpan::of(8 * worker, 8 * worker + 8, info.depth, false);
    return extract_slab(span, info, 128, engine, workspace.data(), workspace.size() * 8, recorder,
                        nullptr, nullptr, slices, cancellation, "noise");
  };
  std::promise<bool> recorded;
  std::future<bool> recording = recorded.get_future();
  std::thread ahead([&] { recorded.set_value(extract(1)); });
  if (recording.wait_for(std::chrono::seconds(20)) != std::future_status::ready) {
    cancellation.cancel();
    turns.wake();
    ahead.join();
    FAIL() << "worker 1 waited for its turn instead of taking more chunks";
  }
  ahead.join();
  ASSERT_TRUE(recording.get());
  EXPECT_GT(turns.most_chunks_taken(), kChunksPerWorker);
  ASSERT_TRUE(extract(0));
  turns.finish_worker(0);
  turns.finish_worker(1);
  ASSERT_EQ(turns.status(), Status::ok);
  writer->finish();
  EXPECT_TRUE(test::read_bytes(dir.file("slabs.ply")) == test::read_bytes(dir.file("one.ply")));
}

// The same through the command line: sparse noise on slices of 512x512, whose slabs of 16
// slices emit about 10 MB, more than the first four chunks hold. How far worker 1 gets ahead of
// the writer depends on how the two threads run; --stats says how many chunks it took (5 to 8
// in every run seen).
TEST(SlabChunkGrowth, GrownChunksAreWrittenAsOneThreadWritesTheSlabs) {
  test::ScratchDirectory dir;
  {
    std::mt19937_64 random(7);
    std::bernoulli_distribution inside(0.01);
    std::ofstream volume(dir / "noise.raw", std::ios::binary);
    for (std::uint32_t i = 0; i < 512u * 512u * 32u; ++i) volume.put(inside(random) ? '\xff' : 0);
  }
  for (const char* extension : {"ply", "stl"}) {
    SCOPED_TRACE(extension);
    const std::string run = std::string("extract noise.raw --raw 512x512x32:u8 -t 128 -q -o ");
    const auto one = test::run_mvox(run + "one." + extension + " --threads 1", dir.path());
    ASSERT_EQ(one.exit_code, 0) << one.output;
    const auto two = test::run_mvox(
        run + "two." + extension + " --threads 2 --slab-slices 16 --stats two.json", dir.path());
    ASSERT_EQ(two.exit_code, 0) << two.output;
    const std::string expected = test::read_bytes(dir.path() / (std::string("one.") + extension));
    EXPECT_GT(expected.size(), std::size_t{4} << 20);
    EXPECT_TRUE(test::read_bytes(dir.path() / (std::string("two.") + extension)) == expected);
    // At most what the plan allows for slabs of 512x512x16 voxels: 8 chunks.
    const std::string report = test::read_bytes(dir.path() / "two.json");
    const std::size_t at = report.find("\"slab_chunks_taken\": ");
    ASSERT_NE(at, std::string::npos) << report;
    const int taken = std::stoi(report.substr(at + 21));
    EXPECT_GE(taken, static_cast<int>(kChunksPerWorker));
    EXPECT_LE(taken, 8);
  }
}

}  // namespace
}  // namespace mvox
