// Interrupts and pipes through the command line (the contract: support/bad_input.h): SIGINT,
// SIGTERM or SIGHUP mid-run, or while waiting for the input, leave nothing and exit with
// 128 + the signal; an error while the input pipe stays open ends the run at once; a reader
// closing the output pipe ends mvox quietly.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "bad_input.h"
#include "command_runner.h"
#include "file_io.h"
#include "mvox_process.h"
#include "refusal.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::read_bytes;

using test::BadInput;
using test::FifoWriter;
using test::MvoxProcess;
using test::run_mvox;

// INTERRUPTS AND PIPES ------------------------------------------------------------------------

// 256x256 slices of 8 bits are 64 KiB, a pipe's capacity: once the test has written slice k
// into the FIFO, mvox has read slice k - 2 at least. The reading thread then sits in read(),
// waiting for slices that do not come, when the signal arrives.
constexpr int kSide = 256;
constexpr int kDepth = 16;

std::string raw_slice(int z) {
  std::string slice(kSide * kSide, '\0');
  for (int y = 64; y < 192; ++y)
    for (int x = 64; x < 192; ++x) slice[y * kSide + x] = z > 0 ? '\xc8' : '\0';
  return slice;
}

// `mvox extract` of volume.raw (kSide x kSide x kDepth, 8 bits) at threshold 128, then `rest`.
std::vector<std::string> raw_job(std::initializer_list<std::string> rest) {
  std::vector<std::string> job = {
      "extract",
      "volume.raw",
      "--raw",
      std::to_string(kSide) + "x" + std::to_string(kSide) + "x" + std::to_string(kDepth) + ":u8",
      "-t",
      "128"};
  job.insert(job.end(), rest);
  return job;
}

std::vector<std::string> interrupted_job() {
  return raw_job(
      {"-o", "previous.ply", "--image", "previous.png", "--stats", "previous.json", "-q"});
}

const char* signal_name(int signal_number) {
  switch (signal_number) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGQUIT: return "SIGQUIT";
    case SIGUSR1: return "SIGUSR1";
    case SIGXCPU: return "SIGXCPU";
  }
  return "?";
}

class Interrupt : public BadInput, public ::testing::WithParamInterface<int> {};

TEST_P(Interrupt, MidRunLeavesNothingAndExitsWith128PlusTheSignal) {
  const int signal_number = GetParam();
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  const auto before = test::tree_snapshot(dir_.path());

  MvoxProcess mvox(interrupted_job(), dir_.path());
  FifoWriter fifo(dir_ / "volume.raw");
  for (int z = 0; z < 3; ++z) ASSERT_TRUE(fifo.write(raw_slice(z))) << "slice " << z;
  // Mid-run for sure: the outputs' three temporaries are there.
  std::size_t temporaries = 0;
  for (const auto& entry : fs::directory_iterator(dir_.path()))
    temporaries += entry.path().filename().string().rfind(".previous.", 0) == 0;
  EXPECT_EQ(temporaries, 3u) << dir_.listing();

  mvox.send(signal_number);
  const MvoxProcess::Ending ending = mvox.finish();
  fifo.close();
  EXPECT_EQ(ending.signal, 0);
  EXPECT_EQ(ending.exit_code, 128 + signal_number);
  EXPECT_EQ(ending.errors, std::string("mvox: error: previous.ply: interrupted by ") +
                               signal_name(signal_number) + "\n");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

// SIGQUIT and the schedulers' SIGUSR1 and SIGXCPU ended mvox with its temporaries on disk.
INSTANTIATE_TEST_SUITE_P(BadInput, Interrupt,
                         ::testing::Values(SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGXCPU),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::string(signal_name(info.param));
                         });

// mvox phantom writes its stack into a hidden folder and renames it into place at the end: an
// interrupt left the folder and its slices behind, and named a slice in it.
TEST_F(BadInput, AnInterruptedPhantomLeavesNoFolder) {
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox({"phantom", "blobs", "-o", "made", "--size", "256x256x20000", "-q"},
                   dir_.path());
  // Mid-run for sure: the staging folder holds a slice.
  bool writing = false;
  for (int wait = 0; wait < 2000 && !writing; ++wait) {
    for (const auto& entry : fs::directory_iterator(dir_.path()))
      if (entry.path().filename().string().rfind(".made.", 0) == 0 && !fs::is_empty(entry.path()))
        writing = true;
    if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(writing) << dir_.listing();
  mvox.send(SIGTERM);
  const MvoxProcess::Ending ending = mvox.finish();
  EXPECT_EQ(ending.exit_code, 128 + SIGTERM);
  EXPECT_EQ(ending.errors, "mvox: error: made: interrupted by SIGTERM\n");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

// A job that fails mid-volume while the FIFO it reads from stays open and silent: the reading
// thread is blocked in read(), and mvox must still end at once with its error (read
// cancellation, src/read/read_cancellation.h), not wait for a writer that may never close.
TEST_F(BadInput, AnErrorWhileTheInputPipeStaysOpenEndsTheRunAtOnce) {
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  std::vector<std::string> job = interrupted_job();
  // The frame after slice 5 cannot be written, its name being taken by a directory: an error
  // mid-volume. (A placement past float's range, used before, is now refused before the run.)
  ASSERT_TRUE(fs::create_directories(dir_ / "frames/frame_0005.png"));
  for (const char* extra : {"--frames", "frames", "--every", "5"}) job.push_back(extra);
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox(job, dir_.path());
  FifoWriter fifo(dir_ / "volume.raw");
  // Seven slices are just enough for the error (found by trying; the picture's normals keep the
  // engine a slice behind): the reader, reading ahead, is then blocked in read() for the eighth.
  for (int z = 0; z < 7; ++z) ASSERT_TRUE(fifo.write(raw_slice(z))) << "slice " << z;
  // The FIFO stays open (no end of file) until after mvox has finished; finish() fails the test
  // if that takes 60 s.
  const MvoxProcess::Ending ending = mvox.finish();
  fifo.close();
  EXPECT_EQ(ending.exit_code, 1);
  EXPECT_NE(ending.errors.find("mvox: error: frames/frame_0005.png: "), std::string::npos)
      << ending.errors;
  EXPECT_EQ(std::count(ending.errors.begin(), ending.errors.end(), '\n'), 1) << ending.errors;
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

// The same with slab threads: a writer that fails (no space on /dev/full) while the thread that
// fans the FIFO's slices out to the workers is blocked in read() for the seventh slice.
TEST_F(BadInput, AnErrorWhileSlabThreadsReadAnOpenPipeEndsTheRunAtOnce) {
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  const std::vector<std::string> job =
      raw_job({"-o", "/dev/full", "--format", "obj", "--threads", "2", "--slab-slices", "4", "-q"});
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox(job, dir_.path());
  FifoWriter fifo(dir_ / "volume.raw");
  // Six slices of noise: the first slab's OBJ text fills the writer's buffer many times over,
  // and the reader has given the second slab all it has. The pipe holds all six, so that they
  // go in even when the writer fails on the full device before the reader has taken them.
  ASSERT_TRUE(fifo.hold(std::size_t{6} * kSide * kSide)) << "the pipe cannot hold six slices";
  std::uint64_t state = 11;
  for (int z = 0; z < 6; ++z) {
    std::string slice(kSide * kSide, '\0');
    for (char& c : slice) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      c = static_cast<char>(state >> 56);
    }
    ASSERT_TRUE(fifo.write(slice)) << "slice " << z;
  }
  // finish() fails the test if mvox takes 60 s: it would wait for the FIFO to close.
  const MvoxProcess::Ending ending = mvox.finish();
  fifo.close();
  EXPECT_EQ(ending.exit_code, 1);
  EXPECT_EQ(ending.errors, "mvox: error: /dev/full: write failed: No space left on device\n");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

// True once a thread of process `pid` waits in open() for a FIFO's writer.
bool waits_for_fifo_writer(pid_t pid) {
  std::error_code error;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", error))
    if (read_bytes((task.path() / "wchan").string()) == "wait_for_partner") return true;
  return false;
}

TEST_F(BadInput, InterruptWhileWaitingForTheInputNamesIt) {
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox(interrupted_job(), dir_.path());
  // No writer: mvox blocks in open(), before any output exists.
  bool waiting = false;
  for (int i = 0; i < 1000 && !waiting; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    waiting = waits_for_fifo_writer(mvox.pid());
  }
  if (!waiting) GTEST_SKIP() << "cannot see mvox wait in open() (/proc/PID/task/*/wchan)";
  mvox.send(SIGINT);
  const MvoxProcess::Ending ending = mvox.finish();
  EXPECT_EQ(ending.exit_code, 130);
  EXPECT_EQ(ending.errors, "mvox: error: volume.raw: interrupted by SIGINT\n");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

TEST_F(BadInput, ReaderClosingTheOutputPipeEndsMvoxQuietly) {
  // `mvox extract ... -o - | head -c 10`: a mesh far larger than the pipe's 64 KiB, so mvox is
  // still writing when the reader goes.
  ASSERT_EQ(run_mvox("phantom sphere -o big --size 96x96x64 -q", dir_.path()).exit_code, 0);
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox({"extract", "big", "-t", "128", "-o", "-", "--image", "previous.png", "--stats",
                    "previous.json", "-q"},
                   dir_.path(), /*own_stdout=*/true);
  EXPECT_EQ(mvox.read_stdout(10), "ply\nformat");
  mvox.close_stdout();
  const MvoxProcess::Ending ending = mvox.finish();
  // As `cat` or `grep` end in a pipeline: killed by SIGPIPE (status 141 in the shell), no
  // message; the picture and the report, which could not appear together with the mesh, do not.
  EXPECT_EQ(ending.signal, SIGPIPE) << "exit code " << ending.exit_code << ": " << ending.errors;
  EXPECT_EQ(ending.errors, "");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

}  // namespace
}  // namespace mvox
