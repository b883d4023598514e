// --largest and --min-faces: connected pieces of the surface, on volumes whose pieces are known
// (balls apart, a voxel alone). What is kept is exactly the surface of a volume holding only the
// kept pieces (the same PLY data, byte for byte: vertices keep their order), alone or per label.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "volume_files.h"

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;

constexpr int kSize = 48;

struct Ball {
  int x, y, z, r2;
  std::uint8_t label;
};
// Three balls apart (radius^2 100, 30 and 9) and one voxel, in labels 1 and 2.
const std::vector<Ball> kBalls = {
    {14, 14, 14, 100, 1}, {34, 30, 30, 30, 1}, {12, 36, 36, 9, 2}, {36, 10, 40, 0, 2}};

// The volume with the balls whose index `keep` accepts, each voxel its ball's label.
template <class Keep>
std::vector<unsigned char> volume(Keep keep) {
  std::vector<unsigned char> v(kSize * kSize * kSize, 0);
  for (std::size_t b = 0; b < kBalls.size(); ++b) {
    if (!keep(b)) continue;
    const Ball& ball = kBalls[b];
    for (int z = 0; z < kSize; ++z)
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
          const int d2 = (x - ball.x) * (x - ball.x) + (y - ball.y) * (y - ball.y) +
                         (z - ball.z) * (z - ball.z);
          if (d2 <= ball.r2) v[(z * kSize + y) * kSize + x] = ball.label;
        }
  }
  return v;
}

const std::string kRaw = " --raw 48x48x48:u8 ";

// The PLY data of `volume` at threshold 1.
std::string reference(const ScratchDirectory& dir, const std::vector<unsigned char>& v) {
  test::volume_files::write_file(dir / "ref.raw", "", v);
  EXPECT_EQ(run_mvox("extract ref.raw" + kRaw + "-t 1 -o ref.ply -q", dir.path()).exit_code, 0);
  return test::ply_body(dir / "ref.ply");
}

TEST(PiecesCli, LargestKeepsTheBiggestBallAndMinFacesTheBallsAboveIt) {
  ScratchDirectory dir;
  test::volume_files::write_file(dir / "all.raw", "", volume([](std::size_t) { return true; }));
  ASSERT_EQ(run_mvox("extract all.raw" + kRaw + "-t 1 -o big.ply --largest --stats s.json -q",
                     dir.path())
                .exit_code,
            0);
  EXPECT_TRUE(test::ply_body(dir / "big.ply") == reference(dir, volume([](std::size_t b) { return b == 0; })));
  const std::string report = test::read_bytes(dir / "s.json");
  EXPECT_NE(report.find("\"pieces\": 4, \"pieces_kept\": 1"), std::string::npos) << report;
  // The pieces have 1904, 584, 176 and 8 polygons (a voxel alone is an octahedron): 200
  // keeps the two largest.
  ASSERT_EQ(run_mvox("extract all.raw" + kRaw + "-t 1 -o some.ply --min-faces 200 -q", dir.path())
                .exit_code,
            0);
  EXPECT_TRUE(test::ply_body(dir / "some.ply") == reference(dir, volume([](std::size_t b) { return b < 2; })));
  ASSERT_EQ(run_mvox("extract all.raw" + kRaw + "-t 1 -o specks.ply --min-faces 9 --format ply -q",
                     dir.path())
                .exit_code,
            0);
  EXPECT_TRUE(test::ply_body(dir / "specks.ply") == reference(dir, volume([](std::size_t b) { return b < 3; })))
      << "--min-faces 9 drops the voxel alone (8 faces) and nothing else";
}

TEST(PiecesCli, WithLabelsEachLabelKeepsItsOwnLargestPiece) {
  ScratchDirectory dir;
  test::volume_files::write_file(dir / "labels.raw", "", volume([](std::size_t) { return true; }));
  ASSERT_EQ(run_mvox("extract labels.raw" + kRaw + "--labels -o 'l_{label}.ply' --largest -q",
                     dir.path())
                .exit_code,
            0);
  // Label 1's largest is ball 0; label 2's is ball 2 (the voxel is the smaller piece). As masks,
  // the kept balls have label 1 and 2 both at threshold 1.
  EXPECT_TRUE(test::ply_body(dir / "l_1.ply") == reference(dir, volume([](std::size_t b) { return b == 0; })));
  EXPECT_TRUE(test::ply_body(dir / "l_2.ply") == reference(dir, volume([](std::size_t b) { return b == 2; })));
  // A label whose every piece is dropped gets no file.
  ASSERT_EQ(run_mvox("extract labels.raw" + kRaw + "--labels -o 'm_{label}.ply' --min-faces 200 "
                     "--stats s.json -q",
                     dir.path())
                .exit_code,
            0);
  EXPECT_TRUE(test::read_bytes(dir / "m_1.ply").size() > 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "m_2.ply"));
  EXPECT_NE(test::read_bytes(dir / "s.json").find("\"labels_dropped\": [2]"), std::string::npos);
}

TEST(PiecesCli, PiecesNeedAMeshAndNoPictureOrNormals) {
  ScratchDirectory dir;
  test::volume_files::write_file(dir / "all.raw", "", volume([](std::size_t) { return true; }));
  const std::string job = "extract all.raw" + kRaw + "-t 1 ";
  expect_one_line_error(run_mvox(job + "-o m.ply --largest --image p.png", dir.path()),
                        "--largest: not with a picture", 2);
  expect_one_line_error(run_mvox(job + "-o m.ply --min-faces 5 --normals", dir.path()),
                        "--min-faces: not with --normals", 2);
  expect_one_line_error(run_mvox(job + "-o m.ply --min-faces 0", dir.path()), "--min-faces", 2);
  expect_one_line_error(run_mvox(job + "-o m.ply --largest --decimate 0.5", dir.path()),
                        "--largest: not with --decimate", 2);
  expect_one_line_error(run_mvox(job + "--largest --image p.png", dir.path()),
                        "--largest: keeps pieces of the mesh: give -o", 2);
}

}  // namespace
}  // namespace mvox
