// --interpolate from the command line: every mesh format holds the moved vertices and the same
// faces, the report and the files say so, the picture draws the moved surface, and threads give
// the same bytes. (The engine's side: tests/core/interpolated_voxels_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
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

// A torus phantom as an image stack in `dir`/stack.
void make_stack(const ScratchDirectory& dir) { test::make_phantom_stack(dir, "torus", "40x36x22"); }

TEST(InterpolateCli, EveryFormatHoldsTheMovedVerticesAndTheSameFaces) {
  ScratchDirectory dir;
  make_stack(dir);
  for (const char* outputs : {"-o midpoints.ply", "-o moved.ply --interpolate",
                              "-o moved.obj --interpolate", "-o moved.stl --interpolate"})
    expect_success(std::string("extract stack -t 100 -q ") + outputs, dir);
  const PlyMesh midpoints = read_ply(dir / "midpoints.ply");
  const PlyMesh moved = read_ply(dir / "moved.ply");
  test::expect_engines_faces_with_moved_vertices(midpoints, moved);

  const test::ObjFile obj = test::read_obj(dir / "moved.obj");
  EXPECT_EQ(obj.positions, moved.positions);
  EXPECT_EQ(obj.faces.size(), moved.face_count());

  // STL: triangles by value, each corner one of the PLY's moved vertices, welded closed.
  const test::StlFile stl = test::expect_corners_among(dir / "moved.stl", moved);
  EXPECT_EQ(test::normal_problems(stl), "");
  const test::Topology welded = test::analyse(test::welded(stl));
  EXPECT_EQ(welded.vertices, moved.vertex_count());
  EXPECT_TRUE(welded.closed_and_consistent()) << test::describe(welded);
}

TEST(InterpolateCli, TheReportTheSummaryAndTheFileSaySo) {
  ScratchDirectory dir;
  make_stack(dir);
  const auto moved =
      run_mvox("extract stack -t 100 -o moved.ply --interpolate --stats moved.json", dir.path());
  ASSERT_EQ(moved.exit_code, 0) << moved.output;
  EXPECT_NE(moved.output.find("vertices interpolated"), std::string::npos) << moved.output;
  EXPECT_NE(test::read_file_bytes(dir / "moved.json").find("\"interpolated\": true"),
            std::string::npos);
  EXPECT_NE(test::read_file_bytes(dir / "moved.ply").find("merge-rules, interpolated vertices"),
            std::string::npos);
  expect_success("extract stack -t 100 -o plain.ply -q --stats plain.json", dir);
  EXPECT_NE(test::read_file_bytes(dir / "plain.json").find("\"interpolated\": false"),
            std::string::npos);
  expect_success("extract stack -t 100 -o cubes.ply -q --method cubes --stats cubes.json", dir);
  EXPECT_NE(test::read_file_bytes(dir / "cubes.json").find("\"interpolated\": true"),
            std::string::npos);
  const auto help = run_mvox("extract --help", dir.path());
  EXPECT_NE(help.output.find("--interpolate"), std::string::npos);
}

TEST(InterpolateCli, ThePictureDrawsTheMovedSurfaceAndThreadsGiveTheSameBytes) {
  ScratchDirectory dir;
  make_stack(dir);
  expect_success("extract stack -t 100 -q --image plain.png --flat", dir);
  expect_success(
      "extract stack -t 100 -q --image moved.png --flat -o moved.ply --interpolate "
      "--threads 1",
      dir);
  EXPECT_NE(test::read_file_bytes(dir / "moved.png"), test::read_file_bytes(dir / "plain.png"));
  for (const char* threads : {"2", "3"}) {
    const std::string name = std::string("threads") + threads;
    expect_success("extract stack -t 100 -q --image " + name + ".png --flat -o " + name +
                       ".ply --interpolate --threads " + threads + " --slab-slices 4",
                   dir);
    EXPECT_EQ(test::read_file_bytes(dir / (name + ".png")),
              test::read_file_bytes(dir / "moved.png"))
        << name;
    EXPECT_EQ(test::read_file_bytes(dir / (name + ".ply")),
              test::read_file_bytes(dir / "moved.ply"))
        << name;
  }
}

}  // namespace
}  // namespace mvox
