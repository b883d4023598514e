// Pictures from the command line: mvox extract --image/--frames, mvox demo's demo.png, mvox
// render, PLY normals, and their errors.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "command_runner.h"
#include "mvox_process.h"
#include "ply_reader.h"

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

cv::Mat read_gray(const std::string& path) { return cv::imread(path, cv::IMREAD_UNCHANGED); }

// A torus stack on disk (image files), as a user would have one.
void make_torus_stack(const ScratchDirectory& dir) {
  ASSERT_EQ(run_mvox("phantom torus -o stack --size 40x36x22 -q", dir.path()).exit_code, 0);
}

TEST(PictureCli, DemoWritesADemoPngOfThePhantom) {
  ScratchDirectory dir;
  const auto result = run_mvox("demo --size 48 -q", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const cv::Mat picture = read_gray(dir / "demo.png");
  ASSERT_FALSE(picture.empty());
  EXPECT_EQ(picture.type(), CV_8UC1);
  EXPECT_EQ(picture.cols, 512);  // the paper's size, the default
  EXPECT_EQ(picture.rows, 512);
  EXPECT_GT(cv::countNonZero(picture), 512 * 512 / 10);  // the phantom fills part of it
  EXPECT_EQ(dir.listing(), "demo.ply demo.png ");
}

TEST(PictureCli, ExtractCanWriteOnlyAPicture) {
  ScratchDirectory dir;
  make_torus_stack(dir);
  const auto result =
      run_mvox("extract stack -t 128 --image torus.png --image-size 200x120", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("torus.png"), std::string::npos) << result.output;
  const cv::Mat picture = read_gray(dir / "torus.png");
  EXPECT_EQ(picture.cols, 200);
  EXPECT_EQ(picture.rows, 120);
  EXPECT_GT(cv::countNonZero(picture), 0);
  EXPECT_EQ(dir.listing(), "stack torus.png ");  // no mesh, no temporary

  // The report names the picture, what was drawn, and the spacing it was placed with.
  ASSERT_EQ(
      run_mvox("extract stack -t 128 --image t.png --spacing 1,1,2 --stats t.json -q", dir.path())
          .exit_code,
      0);
  const std::string report = file_bytes(dir / "t.json");
  EXPECT_NE(report.find("\"image\": \"t.png\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"spacing\": [1, 1, 2]"), std::string::npos) << report;
  EXPECT_NE(report.find("\"triangles_drawn\": "), std::string::npos) << report;
  EXPECT_EQ(report.find("\"triangles_drawn\": 0,"), std::string::npos) << report;
}

TEST(PictureCli, FramesShowThePictureGrowingAndDoNotChangeTheFinalOne) {
  ScratchDirectory dir;
  make_torus_stack(dir);
  ASSERT_EQ(run_mvox("extract stack -t 128 --image once.png --view 20,30 -q", dir.path()).exit_code,
            0);
  const auto framed =
      run_mvox("extract stack -t 128 --image framed.png --view 20,30 --frames frames --every 5 -q",
               dir.path());
  ASSERT_EQ(framed.exit_code, 0) << framed.output;
  // Taking frames leaves the final picture as it was, to the byte.
  EXPECT_EQ(file_bytes(dir / "once.png"), file_bytes(dir / "framed.png"));

  // After 5, 10, 15, 20 slices, and the complete picture after all 22.
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path() / "frames"))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"frame_0005.png", "frame_0010.png", "frame_0015.png",
                                             "frame_0020.png", "frame_0022.png"}));
  EXPECT_EQ(file_bytes(dir / "frames/frame_0022.png"), file_bytes(dir / "once.png"));
  int drawn_before = -1;
  for (const std::string& name : names) {
    const int drawn = cv::countNonZero(read_gray((dir.path() / "frames" / name).string()));
    EXPECT_GE(drawn, drawn_before) << name << ": the picture only grows";
    drawn_before = drawn;
  }
}

TEST(PictureCli, NormalsInThePlyAreUnitAndPointOutwards) {
  ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 30x30x30 -q", dir.path()).exit_code, 0);
  const auto result = run_mvox("extract stack -t 128 -o sphere.ply --normals -q", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const PlyMesh mesh = read_ply(dir / "sphere.ply");
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  ASSERT_GT(mesh.positions.size(), 100u);
  const float centre = 14.5f;  // the phantom sits at the grid's centre
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    const auto& n = mesh.normals[i];
    EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0f, 1e-5f);
    const float outward = n[0] * (p[0] - centre) + n[1] * (p[1] - centre) + n[2] * (p[2] - centre);
    EXPECT_GT(outward, 0.0f) << "vertex " << i;
  }
}

TEST(PictureCli, RenderDrawsPlyFilesWhateverTheirFormat) {
  ScratchDirectory dir;
  make_torus_stack(dir);
  ASSERT_EQ(run_mvox("extract stack -t 128 -o binary.ply -q", dir.path()).exit_code, 0);
  ASSERT_EQ(run_mvox("extract stack -t 128 -o ascii.ply --ascii -q", dir.path()).exit_code, 0);
  const auto rendered = run_mvox("render binary.ply -o binary.png --view 20,30", dir.path());
  ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
  EXPECT_NE(rendered.output.find("binary.png"), std::string::npos) << rendered.output;
  ASSERT_EQ(run_mvox("render ascii.ply -o ascii.png --view 20,30 -q", dir.path()).exit_code, 0);
  EXPECT_EQ(file_bytes(dir / "binary.png"), file_bytes(dir / "ascii.png"));
  EXPECT_GT(cv::countNonZero(read_gray(dir / "binary.png")), 1000);
  // mvox's surfaces are closed and wound outwards, so skipping faces seen from behind changes
  // nothing.
  ASSERT_EQ(
      run_mvox("render binary.ply -o culled.png --view 20,30 --cull -q", dir.path()).exit_code, 0);
  EXPECT_EQ(file_bytes(dir / "binary.png"), file_bytes(dir / "culled.png"));
}

TEST(PictureCli, ShowWithoutADisplayWarnsAndStillWritesThePicture) {
  ScratchDirectory dir;
  const auto result =
      run_mvox("demo --size 32 --show -q", dir.path(), "env -u DISPLAY -u WAYLAND_DISPLAY");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.rfind("mvox: warning: --show: no display", 0), 0u) << result.output;
  EXPECT_EQ(dir.listing(), "demo.ply demo.png ");
}

// A display that accepts the connection and never answers: Qt would wait for it for ever.
// mvox asks it first, gives up after kDisplayAnswerTimeout, warns and goes on. (MvoxProcess
// fails the test after 60 s: a guard, not a timing.)
TEST(PictureCli, ShowWithADisplayThatNeverAnswersWarnsAndGoesOn) {
  // An abstract socket, listening and never accepting: the kernel completes the connection.
  const std::string number = std::to_string(50000 + getpid() % 9000);
  const std::string path = "/tmp/.X11-unix/X" + number;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path + 1, path.data(), path.size());
  const int server = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_EQ(::bind(server, reinterpret_cast<const sockaddr*>(&address),
                   static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + 1 + path.size())),
            0);
  ASSERT_EQ(::listen(server, 8), 0);
  const char* display = std::getenv("DISPLAY");
  const std::string saved_display = display != nullptr ? display : "";
  ::setenv("DISPLAY", (":" + number).c_str(), 1);
  ::unsetenv("QT_QPA_PLATFORM");

  ScratchDirectory dir;
  make_torus_stack(dir);
  test::MvoxProcess mvox({"extract", "stack", "-t", "128", "--image", "torus.png", "--show", "-q"},
                         dir.path());
  const test::MvoxProcess::Ending ending = mvox.finish();
  ::close(server);
  if (display != nullptr)
    ::setenv("DISPLAY", saved_display.c_str(), 1);
  else
    ::unsetenv("DISPLAY");
  EXPECT_EQ(ending.exit_code, 0);
  EXPECT_EQ(ending.errors, "mvox: warning: --show: the X display \":" + number +
                               "\" accepted a connection but did not answer within 3 s; going "
                               "on without a window\n");
  EXPECT_GT(cv::countNonZero(read_gray(dir / "torus.png")), 100);
}

TEST(PictureCli, PictureErrorsAreOneLineAndLeaveNothing) {
  ScratchDirectory dir;
  make_torus_stack(dir);
  expect_one_line_error(run_mvox("extract stack -t 128 --image out.xyz", dir.path()), "out.xyz");
  expect_one_line_error(run_mvox("extract stack -t 128 --image out", dir.path()), "out");
  expect_one_line_error(run_mvox("extract stack -t 128", dir.path()), "nothing to write");
  expect_one_line_error(run_mvox("extract stack -t 128 --image a.png --image-size 0x9", dir.path()),
                        "--image-size", 2);
  expect_one_line_error(run_mvox("extract stack -t 128 --image a.png --every 0", dir.path()),
                        "--every", 2);
  expect_one_line_error(run_mvox("extract stack -t 128 --image a.png --view 1,2,3,4", dir.path()),
                        "--view", 2);
  // --format: a .png mesh output is otherwise a usage error (no mesh format has .png).
  expect_one_line_error(
      run_mvox("extract stack -t 128 -o a.png --format ply --image a.png", dir.path()), "a.png");
  expect_one_line_error(run_mvox("extract stack -t 128 --image no/dir/a.png", dir.path()),
                        "no/dir/a.png");
  expect_one_line_error(run_mvox("render missing.ply -o a.png", dir.path()), "missing.ply");
  expect_one_line_error(run_mvox("render missing.ply", dir.path()), "-o");
  std::ofstream(dir / "broken.ply") << "ply\nformat ascii 1.0\nelement vertex 1\n";
  expect_one_line_error(run_mvox("render broken.ply -o a.png", dir.path()), "broken.ply");
  EXPECT_EQ(dir.listing(), "broken.ply stack ");
}

}  // namespace
}  // namespace mvox
