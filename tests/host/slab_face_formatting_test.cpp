// STL faces formatted by the slab worker that extracted them, ahead of its turn to write
// (write/mesh/face_formatter.h, pipeline/slab_recorder.h): the recorder keeps the records and the
// vertex counts instead of the engine's batches, the writer appends them, and the file is the one
// a single engine writes, byte for byte. A batch the formatter refuses is recorded as the engine
// made it, so that the writer refuses it in the words of a one-thread run.
#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <random>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "mvox/engine.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_extraction.h"
#include "pipeline/slab_recorder.h"
#include "read/memory/memory_volume_source.h"
#include "write/mesh/face_formatter.h"
#include "write/mesh/ply_writer.h"
#include "write/mesh/stl_writer.h"

namespace mvox {
namespace {

VolumeInfo noise_info(std::uint32_t depth) {
  VolumeInfo info;
  info.width = 19;
  info.height = 13;
  info.depth = depth;
  info.type = SampleType::u8;
  return info;
}

std::vector<std::uint8_t> noise(const VolumeInfo& info) {
  std::mt19937 random(5);
  std::vector<std::uint8_t> samples(std::size_t{info.width} * info.height * info.depth);
  for (auto& sample : samples) sample = static_cast<std::uint8_t>(random() & 0xff);
  return samples;
}

// Scaled, shifted, and mirrored by a rotation with a reflection, so that the formatter has to
// place every corner and reverse every face's winding, as the writer does.
MeshWriterOptions mirrored_options() {
  MeshWriterOptions options;
  options.transform.spacing = {0.5, 1.25, 2.0};
  options.transform.origin = {-3.0, 7.5, 100.0};
  options.transform.axes = {{{0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}}};
  options.comments = {"slab face formatting"};
  return options;
}

EngineOptions with_geometry() {
  EngineOptions engine;
  engine.polygon_geometry = true;  // STL needs the polygons' corners
  return engine;
}

// Every chunk the recorder fills, kept; the writer's turn never comes while it records.
class KeepingHandover final : public SlabRecorder::Handover {
 public:
  SlabChunk* take() override {
    chunks.emplace_back();
    chunks.back().reserve(with_geometry(), StlWriter::kMostBytesPerPolygon);
    return &chunks.back();
  }
  void full(SlabChunk*) override {}
  std::deque<SlabChunk> chunks;
};

// The whole volume as one slab through a recorder with `writer`'s formatter, its chunks then
// replayed into `writer`.
void record_then_replay(const std::vector<std::uint8_t>& samples, const VolumeInfo& info,
                        StlWriter& writer, KeepingHandover& handover) {
  const auto formatter = writer.face_formatter();
  ASSERT_NE(formatter, nullptr);
  SlabRecorder recorder(handover, &writer.placement(), nullptr, true, formatter.get());
  const EngineOptions engine_options = with_geometry();
  std::vector<std::uint64_t> workspace(
      engine_workspace_bytes(info.width, info.height, engine_options) / 8 + 1);
  Engine engine;
  ASSERT_EQ(engine.init(workspace.data(), workspace.size() * 8, info.width, info.height, 128,
                        engine_options, &recorder),
            Status::ok);
  ASSERT_TRUE(recorder.start(0));
  const std::size_t slice_bytes = std::size_t{info.width} * info.height;
  for (std::uint32_t z = 0; z < info.depth; ++z) {
    SliceView slice;
    slice.samples = samples.data() + z * slice_bytes;
    slice.width = info.width;
    slice.height = info.height;
    slice.type = SampleType::u8;
    slice.row_stride_bytes = info.width;
    ASSERT_EQ(engine.push_slice(slice), Status::ok) << z;
    if (z == 0) recorder.own_vertices_only();
  }
  ASSERT_EQ(engine.finish(), Status::ok);
  SlabSummary summary;
  summary.counters = engine.counters();
  recorder.end(summary);
  SlabReplay replay(&writer);
  for (SlabChunk& chunk : handover.chunks) ASSERT_EQ(replay.replay(chunk), Status::ok);
}

TEST(SlabFaceFormatting, RecordedFacesAreFormattedRecordsThatReplayAsOneEnginesFile) {
  const VolumeInfo info = noise_info(23);
  const auto samples = noise(info);
  test::ScratchDirectory dir;
  {
    MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                              info.width);
    StlWriter writer(dir.file("one.stl"), mirrored_options());
    run_pipeline(source, 128, with_geometry(), writer, "noise");
    writer.finish();
  }
  KeepingHandover handover;
  StlWriter writer(dir.file("recorded.stl"), mirrored_options());
  record_then_replay(samples, info, writer, handover);
  writer.finish();
  EXPECT_TRUE(test::read_bytes(dir.file("recorded.stl")) == test::read_bytes(dir.file("one.stl")));

  // What was recorded: formatted records and vertex counts, not the engine's batches.
  std::size_t formatted = 0, counted = 0, other = 0, record_bytes = 0;
  for (const SlabChunk& chunk : handover.chunks) {
    for (const SlabChunk::Call& call : chunk.calls) {
      if (call.kind == SlabChunk::Kind::formatted_faces)
        ++formatted;
      else if (call.kind == SlabChunk::Kind::vertex_count)
        ++counted;
      else
        ++other;
    }
    record_bytes += chunk.formatted.size();
    EXPECT_TRUE(chunk.polygons.empty());
    EXPECT_TRUE(chunk.geometry.empty());
    EXPECT_EQ(chunk.placed_count, 0u);
  }
  EXPECT_GT(formatted, 1u);
  EXPECT_GT(counted, 1u);
  EXPECT_EQ(other, 0u);
  EXPECT_EQ(record_bytes, writer.faces_written() * 50);
}

TEST(SlabFaceFormatting, OnlyAFormatWithoutIndicesInItsFaceRecordsHasAFormatter) {
  test::ScratchDirectory dir;
  EXPECT_EQ(PlyWriter(dir.file("m.ply")).face_formatter(), nullptr);
  EXPECT_NE(StlWriter(dir.file("m.stl")).face_formatter(), nullptr);
  // And a writer that writes vertex records refuses vertices counted without them.
  PlyWriter ply(dir.file("n.ply"));
  EXPECT_EQ(ply.consume_vertex_count(3), Status::sink_refused);
  ASSERT_NE(ply.error(), nullptr);
  EXPECT_NE(std::string(ply.error()->what()).find("internal error"), std::string::npos);
}

// Slab workers with their formatters, 2, 3 and 8 of them on 4-slice slabs, write one engine's
// file; and a vertex that leaves float's range in the middle of the volume is refused in the
// same words as one engine refuses it (the CLI refuses such a placement before the run, a
// library caller may not).
TEST(SlabFaceFormatting, SlabWorkersWriteOneEnginesStlAndRefuseWhatItRefuses) {
  for (const bool far : {false, true}) {
    SCOPED_TRACE(far ? "a vertex beyond float's range" : "every vertex in range");
    const VolumeInfo info = noise_info(far ? 400 : 41);
    const auto samples = noise(info);
    MeshWriterOptions options = mirrored_options();
    if (far) options.transform.spacing = {1.0, 1.0, 1e36};  // z beyond 340 leaves float's range
    test::ScratchDirectory dir;
    std::string one_error, one_bytes;
    {
      MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                                info.width);
      StlWriter writer(dir.file("m.stl"), options);  // the same name: the same messages
      run_pipeline(source, 128, with_geometry(), writer, "noise");
      try {
        writer.finish();
        one_bytes = test::read_bytes(dir.file("m.stl"));
      } catch (const Error& error) {
        one_error = error.what();
      }
    }
    EXPECT_EQ(one_error.empty(), !far) << one_error;
    for (const unsigned threads : {2u, 3u, 8u}) {
      SCOPED_TRACE(std::to_string(threads) + " workers");
      MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                                info.width);
      StlWriter writer(dir.file("m.stl"), options);
      SlabOptions slabs;
      slabs.threads = threads;
      slabs.slab_slices = 4;
      run_slab_pipeline(source, 128, with_geometry(), &writer, slabs, "noise");
      std::string error_text;
      try {
        writer.finish();
      } catch (const Error& error) {
        error_text = error.what();
      }
      EXPECT_EQ(error_text, one_error);
      if (!far) EXPECT_TRUE(test::read_bytes(dir.file("m.stl")) == one_bytes);
    }
  }
}

}  // namespace
}  // namespace mvox
