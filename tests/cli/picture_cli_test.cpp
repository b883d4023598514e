// Pictures from the command line: mvox extract --image/--frames, mvox demo's demo.png, mvox
// render, PLY normals, and their errors.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "mvox/zbuffer_renderer.h"
#include "mvox_process.h"
#include "read/ply/ply_reader.h"

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;
using test::write_bytes;

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

TEST(PictureCli, TheDemoPictureIsACutawayWithCaps) {
  // The README's picture: the skull cut open, its cut capped in the flat cap shade, which
  // lighting gives almost nowhere (--cut 0 shows the closed skull).
  ScratchDirectory dir;
  ASSERT_EQ(run_mvox("demo --size 64 -q", dir.path()).exit_code, 0);
  ASSERT_EQ(
      run_mvox("demo --size 64 -q --cut 0 -o whole.ply --image whole.png", dir.path()).exit_code,
      0);
  const std::uint8_t cap = Lighting().cap;
  auto cap_share = [cap](const cv::Mat& picture) {
    return static_cast<double>(cv::countNonZero(picture == cap)) /
           std::max(1, cv::countNonZero(picture));
  };
  const double cutaway = cap_share(read_gray(dir / "demo.png"));
  const double whole = cap_share(read_gray(dir / "whole.png"));
  EXPECT_GT(cutaway, 0.08) << "the skull's cut is capped";
  EXPECT_LT(whole, 0.02);
  // The mesh is the whole surface either way: the cut is the picture's.
  EXPECT_EQ(test::read_bytes(dir / "demo.ply"), test::read_bytes(dir / "whole.ply"));
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

TEST(PictureCli, RenderCutsAwayAndCapsOnlyMeshesItMayTakeAsClosed) {
  // mvox render takes any PLY file, so it caps a cut only with --cull (the mesh is closed and
  // consistently wound); without it the cut only removes what lies in front of the plane.
  ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 30x30x30 -q", dir.path()).exit_code, 0);
  ASSERT_EQ(run_mvox("extract stack -t 128 -o sphere.ply -q", dir.path()).exit_code, 0);
  for (const char* options : {"", "--cut 0.5", "--cut 0.5 --cull"}) {
    ASSERT_EQ(
        run_mvox(std::string("render sphere.ply -o p.png -q ") + options, dir.path()).exit_code, 0)
        << options;
    const cv::Mat picture = read_gray(dir / "p.png");
    const int caps = cv::countNonZero(picture == Lighting().cap);
    const int drawn = cv::countNonZero(picture);
    if (std::string(options).find("--cull") != std::string::npos)
      EXPECT_GT(caps, drawn * 9 / 10) << options << ": a solid ball cut in half is all cap";
    else
      EXPECT_LT(caps, drawn / 50) << options;
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

// Pictures fit the volume whatever its size, and the fit does not depend on the size: a
// spacing of 1e-37 or 1e36 must draw what a spacing of 1 draws. The renderer's float camera
// used to overflow (1e-37: every polygon off-screen) or lose the box (1e36), giving a black
// picture, and the gradient normals fell back to their axes.
TEST(PictureCli, ExtremeSpacingsDrawTheSamePictureAndNormalsAsSpacingOne) {
  ScratchDirectory dir;
  make_torus_stack(dir);
  const std::string job = "extract stack -t 128 --normals --view 20,30 -q";
  ASSERT_EQ(run_mvox(job + " --spacing 1,1,2 -o ref.ply --image ref.png", dir.path()).exit_code, 0);
  const cv::Mat reference = read_gray(dir / "ref.png");
  const PlyMesh reference_mesh = read_ply(dir / "ref.ply");
  ASSERT_GT(cv::countNonZero(reference), 10000);
  for (const double scale : {1e-37, 3e-38, 1e36}) {
    SCOPED_TRACE("spacing scaled by " + std::to_string(scale));
    char spacing[96];
    std::snprintf(spacing, sizeof spacing, "%.17g,%.17g,%.17g", scale, scale, 2 * scale);
    const auto result =
        run_mvox(job + " --spacing " + spacing + " -o scaled.ply --image scaled.png", dir.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    cv::Mat difference;
    cv::absdiff(read_gray(dir / "scaled.png"), reference, difference);
    // Drawn in the box's own frame, both are the same numbers up to rounding.
    EXPECT_LE(cv::countNonZero(difference), static_cast<int>(difference.total() / 1000));
    const PlyMesh mesh = read_ply(dir / "scaled.ply");
    ASSERT_EQ(mesh.vertex_count(), reference_mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
      for (int axis = 0; axis < 3; ++axis) {
        ASSERT_NEAR(mesh.positions[v][axis] / scale, reference_mesh.positions[v][axis], 1e-4)
            << "vertex " << v;
        ASSERT_NEAR(mesh.normals[v][axis], reference_mesh.normals[v][axis], 1e-5) << "vertex " << v;
      }
  }
  // Below that the mesh's floats would lose their bits (at 1e-46 every vertex was 0,0,0): a
  // usage error giving the usable range.
  expect_one_line_error(run_mvox(job + " --spacing 1e-46,1e-46,1e-46 -o x.ply", dir.path()),
                        "--spacing: is too small for float coordinates, got 1e-46 (usable: "
                        "2.35099e-38 to 3.40282e+38)",
                        2);
}

// A unit cube as an ASCII PLY, corners at `low` and `high` on every axis.
void write_cube(const std::string& path, float low, float high) {
  std::ofstream out(path);
  out.precision(9);
  out << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
         "property float z\nelement face 6\nproperty list uchar int vertex_indices\n"
         "end_header\n";
  for (int corner = 0; corner < 8; ++corner)
    out << ((corner & 1) ? high : low) << " " << ((corner & 2) ? high : low) << " "
        << ((corner & 4) ? high : low) << "\n";
  out << "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
}

// mvox render fits any mesh: a cube of subnormal floats (8 times the smallest, 1.1e-44), one
// of 1e-37 and one from -3e38 to 3e38 are drawn exactly like the cube from 0 to 1. They were
// black: the camera's float scale overflowed, or the box's size did.
TEST(PictureCli, RenderDrawsMeshesAtBothEndsOfFloatsRange) {
  ScratchDirectory dir;
  write_cube(dir / "unit.ply", 0.0f, 1.0f);
  write_cube(dir / "subnormal.ply", 0.0f, 8 * std::numeric_limits<float>::denorm_min());
  write_cube(dir / "tiny.ply", 0.0f, 1e-37f);
  write_cube(dir / "huge.ply", -3e38f, 3e38f);
  ASSERT_EQ(run_mvox("render unit.ply -o unit.png --view 30,20 -q", dir.path()).exit_code, 0);
  ASSERT_GT(cv::countNonZero(read_gray(dir / "unit.png")), 10000);
  for (const char* name : {"subnormal", "tiny", "huge"}) {
    const auto result = run_mvox(
        std::string("render ") + name + ".ply -o " + name + ".png --view 30,20 -q", dir.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_EQ(file_bytes(dir / (std::string(name) + ".png")), file_bytes(dir / "unit.png")) << name;
  }
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

// render reads its mesh whole: one beyond the memory at hand is named, with the size it asked
// for, and without extract's hint (it has no --dry-run).
TEST(PictureCli, RenderOutOfMemoryNamesTheMeshAndTheSize) {
  ScratchDirectory dir;
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 100000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  write_bytes(dir / "huge.ply", header);
  std::filesystem::resize_file(dir / "huge.ply", header.size() + std::uintmax_t{1200000000});
  const test::CommandResult result =
      run_mvox("render huge.ply -o a.png", dir.path(), "ulimit -v 400000;");
  expect_one_line_error(result, "huge.ply");
  EXPECT_NE(result.output.find("huge.ply: out of memory: an allocation of 1.1 GiB failed\n"),
            std::string::npos)
      << result.output;
  EXPECT_EQ(dir.listing(), "huge.ply ");
}

TEST(PictureCli, PictureErrorsAreOneLineAndLeaveNothing) {
  ScratchDirectory dir;
  make_torus_stack(dir);
  expect_one_line_error(run_mvox("extract stack -t 128 --image out.xyz", dir.path()), "out.xyz");
  expect_one_line_error(run_mvox("extract stack -t 128 --image out", dir.path()), "out");
  expect_one_line_error(run_mvox("extract stack -t 128", dir.path()), "nothing to write", 2);
  expect_one_line_error(run_mvox("extract stack -t 128 --image a.png --image-size 0x9", dir.path()),
                        "--image-size", 2);
  expect_one_line_error(run_mvox("extract stack -t 128 --image a.png --every 0", dir.path()),
                        "--every", 2);
  expect_one_line_error(run_mvox("extract stack -t 128 --image a.png --view 1,2,3,4", dir.path()),
                        "--view", 2);
  // --format: a .png mesh output is otherwise a usage error (no mesh format has .png).
  expect_one_line_error(
      run_mvox("extract stack -t 128 -o a.png --format ply --image a.png", dir.path()), "a.png", 2);
  expect_one_line_error(run_mvox("extract stack -t 128 --image no/dir/a.png", dir.path()),
                        "no/dir/a.png");
  expect_one_line_error(run_mvox("render missing.ply -o a.png", dir.path()), "missing.ply");
  expect_one_line_error(run_mvox("render missing.ply", dir.path()), "-o", 2);  // a usage error
  std::ofstream(dir / "broken.ply") << "ply\nformat ascii 1.0\nelement vertex 1\n";
  expect_one_line_error(run_mvox("render broken.ply -o a.png", dir.path()), "broken.ply");
  EXPECT_EQ(dir.listing(), "broken.ply stack ");
}

}  // namespace
}  // namespace mvox
