// `mvox extract --frames` and `--show` with slab workers: the frames show the picture growing
// as the workers finish their slabs (slab_picture_follower.h). They are written as the slabs
// are drawn; each shows at least what one engine's frame of the same name shows and never less
// than the frame before it; the last frame and the picture are one engine's, byte for byte; a
// frame that cannot be written fails the run as it fails with one engine, and no frame is
// written after it; the live window opens.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "support/command_runner.h"
#include "support/file_io.h"
#include "support/slab_run_checks.h"

namespace mvox {
namespace {

using test::run_mvox;

// The frame files of `dir`, sorted by name (which sorts them by slices done).
std::vector<std::string> frame_names(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The pixels something was drawn on: the background is 0, and the lighting's ambient term
// keeps every surface pixel above it.
cv::Mat drawn(const std::filesystem::path& frame) {
  const cv::Mat picture = cv::imread(frame.string(), cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(picture.empty()) << frame;
  return picture > 0;
}

// Whether every pixel drawn in `inner` is drawn in `outer`.
bool covers(const cv::Mat& outer, const cv::Mat& inner) {
  return cv::countNonZero(inner & ~outer) == 0;
}

// The "render" object of a --stats report.
std::string render_counters(const std::string& report) {
  const std::size_t start = report.find("\"render\": {");
  EXPECT_NE(start, std::string::npos) << report;
  if (start == std::string::npos) return "";
  return report.substr(start, report.find('}', start) - start);
}

TEST(SlabFrames, FramesGrowSlabBySlabAndEndOnOneEnginesPicture) {
  test::ScratchDirectory dir;
  test::write_noise(dir / "noise.raw", 41 * 23 * 37, 7);
  const std::string input =
      "extract noise.raw --raw 41x23x37:u8 -t 128 -q --slab-slices 4 --every 3 --image-size 96 ";
  const test::CommandResult one =
      run_mvox(input + "--frames f1 --image p1.png --threads 1", dir.path());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const std::vector<std::string> names = frame_names(dir.path() / "f1");
  ASSERT_EQ(names.size(), 13u);  // after 3, 6, ..., 36 slices, and the last after 37
  for (const int threads : {2, 3, 8}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    const std::string frames = "f" + std::to_string(threads);
    const std::string image = "p" + std::to_string(threads) + ".png";
    const std::string plan = run_mvox(input + "--frames " + frames + " --image " + image +
                                          " --threads " + std::to_string(threads) + " --dry-run",
                                      dir.path())
                                 .output;
    EXPECT_NE(plan.find(std::to_string(threads) + " slab workers"), std::string::npos) << plan;
    const std::string with_threads = " --threads " + std::to_string(threads);
    const test::CommandResult run = run_mvox(
        input + "--frames " + frames + " --image " + image + with_threads + " --stats s.json",
        dir.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    ASSERT_EQ(frame_names(dir.path() / frames), names);
    EXPECT_EQ(test::read_bytes(dir / image), test::read_bytes(dir / "p1.png"));
    // The layers composited for the frames are not counted again: the renderer's counters are
    // those of the same workers without frames.
    ASSERT_EQ(
        run_mvox(input + "--image q.png" + with_threads + " --stats t.json", dir.path()).exit_code,
        0);
    EXPECT_EQ(render_counters(test::read_bytes(dir / "s.json")),
              render_counters(test::read_bytes(dir / "t.json")));
    EXPECT_EQ(test::read_bytes(dir.path() / frames / names.back()),
              test::read_bytes(dir.path() / "f1" / names.back()));
    // Written in order, as one engine writes them (the file system's clock may give frames
    // written close together the same time).
    auto written_before = std::filesystem::file_time_type::min();
    for (const std::string& name : names) {
      const auto written = std::filesystem::last_write_time(dir.path() / frames / name);
      EXPECT_GE(written, written_before) << name << " was written before the frame before it";
      written_before = written;
    }
    cv::Mat before;
    for (const std::string& name : names) {
      SCOPED_TRACE(name);
      const cv::Mat now = drawn(dir.path() / frames / name);
      EXPECT_TRUE(covers(now, drawn(dir.path() / "f1" / name))) << "less than one engine shows";
      if (!before.empty()) EXPECT_TRUE(covers(now, before)) << "less than the frame before";
      before = now;
    }
  }
}

// Frames are written as the slabs are drawn, not at the end: the volume comes through a pipe,
// and its last 26 slices only once the frame after 3 slices exists (or after 30 s, which the
// feeder records: frames written only at the end would end so). That frame shows no more than
// the first 11 slices' slabs; the last shows them all.
TEST(SlabFrames, FramesAreWrittenAsTheSlabsAreDrawn) {
  test::ScratchDirectory dir;
  test::write_noise(dir / "noise.raw", 41 * 23 * 37, 7);
  const int first_part = 41 * 23 * 11;
  const std::string feed =
      "{ head -c " + std::to_string(first_part) +
      " noise.raw; for i in $(seq 600); do [ -e f/frame_0003.png ] && break; sleep 0.05; done; "
      "[ -e f/frame_0003.png ] || : > gave_up; tail -c +" +
      std::to_string(first_part + 1) + " noise.raw; } |";
  for (const int threads : {2, 3}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    std::filesystem::remove_all(dir.path() / "f");
    const test::CommandResult run = run_mvox(
        "extract /dev/stdin --raw 41x23x37:u8 -t 128 -q --slab-slices 4 --every 3 "
        "--image-size 96 --frames f --threads " +
            std::to_string(threads),
        dir.path(), feed);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "gave_up"))
        << "no frame was written before the whole volume had come";
    const int first = cv::countNonZero(drawn(dir.path() / "f" / "frame_0003.png"));
    const int last = cv::countNonZero(drawn(dir.path() / "f" / "frame_0037.png"));
    EXPECT_GT(first, 0);
    EXPECT_LT(first, last / 2);
  }
}

TEST(SlabFrames, AFrameThatCannotBeWrittenFailsTheRunAsWithOneEngine) {
  test::ScratchDirectory dir;
  test::write_noise(dir / "noise.raw", 41 * 23 * 37, 7);
  std::filesystem::create_directories(dir.path() / "f" / "frame_0012.png");
  std::string one_engine;
  for (const int threads : {1, 3, 8}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    const test::CommandResult run = run_mvox(
        "extract noise.raw --raw 41x23x37:u8 -t 128 -q --slab-slices 4 --every 3 "
        "--frames f --image p.png -o m.ply --threads " +
            std::to_string(threads),
        dir.path());
    EXPECT_NE(run.exit_code, 0);
    EXPECT_NE(run.output.find("frame_0012.png"), std::string::npos) << run.output;
    EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
    if (threads == 1) one_engine = run.output;
    EXPECT_EQ(run.output, one_engine);
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "p.png"));
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "m.ply"));
    // Workers that had frames to write when the run failed write no more of them.
    for (const std::string& name : frame_names(dir.path() / "f"))
      EXPECT_LE(name, "frame_0012.png") << "written after the run failed";
    std::filesystem::remove_all(dir.path() / "f");
    std::filesystem::create_directories(dir.path() / "f" / "frame_0012.png");
  }
}

// --show with slab workers, on a virtual display: the window opens (no warning), the run ends
// normally and the picture is one engine's. (What the window showed is not checked here;
// LiveWindow's own test checks that images reach it.)
TEST(SlabFrames, TheLiveWindowShowsWorkersPicture) {
  test::ScratchDirectory dir;
  if (test::run_command("command -v xvfb-run", dir.path()).exit_code != 0)
    GTEST_SKIP() << "xvfb-run is not installed (scripts/install_deps.sh installs xvfb)";
  test::write_noise(dir / "noise.raw", 41 * 23 * 37, 7);
  const std::string input = "extract noise.raw --raw 41x23x37:u8 -t 128 --slab-slices 4 ";
  ASSERT_EQ(run_mvox(input + "-q --image p1.png --threads 1", dir.path()).exit_code, 0);
  const test::CommandResult run = run_mvox(input + "--image p3.png --show --threads 3", dir.path(),
                                           "env -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM xvfb-run -a");
  if (run.output.find("built without") != std::string::npos)
    GTEST_SKIP() << "mvox was built without its live window: " << run.output;
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("warning"), std::string::npos) << run.output;
  EXPECT_EQ(test::read_bytes(dir / "p3.png"), test::read_bytes(dir / "p1.png"));
}

}  // namespace
}  // namespace mvox
