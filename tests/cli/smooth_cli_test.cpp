// --smooth N from the command line: every mesh format holds the smoothed vertices and the
// engine's faces, the report, the summary and the file say so, the picture draws the smoothed
// surface, normals are written at the smoothed positions, threads change nothing (one engine
// smooths), and the memory plan counts the layers held. (The smoothing itself:
// tests/host/edge_smoothing_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cli_mesh_checks.h"
#include "command_runner.h"
#include "mesh_topology.h"
#include "obj_reader.h"
#include "ply_mesh.h"
#include "read/ply/ply_reader.h"
#include "stl_reader.h"

namespace mvox {
namespace {

using test::expect_success;
using test::run_mvox;
using test::ScratchDirectory;

// A torus phantom as an image stack in `dir`/stack: a binary surface, terraced.
void make_stack(const ScratchDirectory& dir) { test::make_phantom_stack(dir, "torus", "40x36x22"); }

TEST(SmoothCli, EveryFormatHoldsTheSmoothedVerticesAndTheEnginesFaces) {
  ScratchDirectory dir;
  make_stack(dir);
  for (const char* outputs :
       {"-o plain.ply", "-o smooth.ply --smooth 8", "-o smooth.obj --smooth 8",
        "-o smooth.stl --smooth 8", "-o normals.ply --smooth 8 --normals"})
    expect_success(std::string("extract stack -t 100 -q ") + outputs, dir);
  const PlyMesh plain = read_ply(dir / "plain.ply");
  const PlyMesh smooth = read_ply(dir / "smooth.ply");
  test::expect_engines_faces_with_moved_vertices(plain, smooth);

  EXPECT_EQ(test::read_obj(dir / "smooth.obj").positions, smooth.positions);
  const test::StlFile stl = test::expect_corners_among(dir / "smooth.stl", smooth);
  EXPECT_TRUE(test::analyse(test::welded(stl)).closed_and_consistent());

  // Normals at the smoothed positions: the same vertices, and a unit normal each.
  const PlyMesh normals = read_ply(dir / "normals.ply");
  EXPECT_EQ(normals.positions, smooth.positions);
  ASSERT_EQ(normals.normals.size(), normals.vertex_count());
  for (const auto& n : normals.normals)
    ASSERT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-4);
}

TEST(SmoothCli, TheReportTheSummaryTheFileAndThePlanSaySo) {
  ScratchDirectory dir;
  make_stack(dir);
  const auto run =
      run_mvox("extract stack -t 100 -o smooth.ply --smooth 8 --stats s.json", dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("smoothed 8 times"), std::string::npos) << run.output;
  const std::string report = test::read_file_bytes(dir / "s.json");
  EXPECT_NE(report.find("\"smooth_iterations\": 8"), std::string::npos);
  EXPECT_NE(report.find("smoothing (11 layers held)"), std::string::npos) << report;
  EXPECT_NE(test::read_file_bytes(dir / "smooth.ply").find("smoothed 8 times"), std::string::npos);
  const auto help = run_mvox("extract --help", dir.path());
  EXPECT_NE(help.output.find("--smooth"), std::string::npos);
  const auto bad = run_mvox("extract stack -t 100 -o x.ply --smooth -1", dir.path());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

TEST(SmoothCli, ThePictureDrawsTheSmoothedSurfaceAndThreadsChangeNothing) {
  ScratchDirectory dir;
  make_stack(dir);
  expect_success("extract stack -t 100 -q --image plain.png --flat", dir);
  expect_success("extract stack -t 100 -q --image smooth.png --flat -o smooth.ply --smooth 6", dir);
  EXPECT_NE(test::read_file_bytes(dir / "smooth.png"), test::read_file_bytes(dir / "plain.png"));
  expect_success(
      "extract stack -t 100 -q --image threads.png --flat -o threads.ply --smooth 6 "
      "--threads 3 --slab-slices 4",
      dir);
  EXPECT_EQ(test::read_file_bytes(dir / "threads.png"), test::read_file_bytes(dir / "smooth.png"));
  EXPECT_EQ(test::read_file_bytes(dir / "threads.ply"), test::read_file_bytes(dir / "smooth.ply"));
}

}  // namespace
}  // namespace mvox
