// --decimate / --max-error from the command line: every mesh format holds a closed, manifold,
// simplified surface of about the share asked for; the report and the summary give the counts;
// the picture draws it (flat); threads change nothing; it combines with --smooth; and what it
// cannot do is refused in one line. (The decimation itself: tests/host/layer_decimation_test.)
#include <gtest/gtest.h>

#include <string>

#include "cli_mesh_checks.h"
#include "command_runner.h"
#include "mesh_topology.h"
#include "obj_reader.h"
#include "ply_mesh.h"
#include "postprocess/layer_decimation.h"
#include "read/ply/ply_reader.h"
#include "stl_reader.h"

namespace mvox {
namespace {

using test::expect_success;
using test::run_mvox;
using test::ScratchDirectory;

// A blobs phantom as an image stack in `dir`/stack.
void make_stack(const ScratchDirectory& dir) { test::make_phantom_stack(dir, "blobs", "48x44x40"); }

void expect_closed_manifold(const PlyMesh& ply, const std::string& what) {
  const test::Topology topology = test::analyse(test::to_mesh(ply));
  EXPECT_TRUE(topology.closed_and_consistent()) << what << ": " << test::describe(topology);
}

TEST(DecimateCli, EveryFormatHoldsAClosedSimplifiedSurface) {
  if (!decimation_available()) GTEST_SKIP() << "built without meshoptimizer";
  ScratchDirectory dir;
  make_stack(dir);
  for (const char* outputs :
       {"-o full.ply --triangulate", "-o less.ply --decimate 0.2 --stats less.json",
        "-o less.obj --decimate 0.2", "-o less.stl --decimate 0.2",
        "-o both.ply --smooth 5 --decimate 0.3", "-o bound.ply --max-error 0.5"})
    expect_success(std::string("extract stack -t 100 -q ") + outputs, dir);
  const PlyMesh full = read_ply(dir / "full.ply");
  const PlyMesh less = read_ply(dir / "less.ply");
  ASSERT_GT(full.face_count(), 5000u);
  EXPECT_LT(less.face_count(), full.face_count() * 0.26);
  EXPECT_GT(less.face_count(), full.face_count() * 0.1);
  EXPECT_EQ(less.face_indices.size(), 3 * less.face_count());  // triangles only
  expect_closed_manifold(less, "less.ply");
  expect_closed_manifold(read_ply(dir / "both.ply"), "both.ply");
  const PlyMesh bound = read_ply(dir / "bound.ply");
  expect_closed_manifold(bound, "bound.ply");
  EXPECT_LT(bound.face_count(), full.face_count());

  const test::ObjFile obj = test::read_obj(dir / "less.obj");
  EXPECT_EQ(obj.positions, less.positions);
  EXPECT_EQ(obj.faces.size(), less.face_count());
  const test::StlFile stl = test::read_stl(dir / "less.stl");
  EXPECT_EQ(stl.triangles.size(), less.face_count());
  EXPECT_TRUE(test::analyse(test::welded(stl)).closed_and_consistent());

  const std::string report = test::read_file_bytes(dir / "less.json");
  EXPECT_NE(report.find("\"decimation\": {\"ratio\": 0.2, \"max_error_voxels\": 0, "
                        "\"triangles_in\": " +
                        std::to_string(full.face_count()) +
                        ", \"triangles_out\": " + std::to_string(less.face_count()) +
                        ", \"vertices_out\": " + std::to_string(less.vertex_count()) + "}"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("\"faces_written\": " + std::to_string(less.face_count())),
            std::string::npos);
}

TEST(DecimateCli, ThePictureDrawsItAndThreadsChangeNothing) {
  if (!decimation_available()) GTEST_SKIP() << "built without meshoptimizer";
  ScratchDirectory dir;
  make_stack(dir);
  const auto one =
      run_mvox("extract stack -t 100 -o one.ply --image one.png --decimate 0.2", dir.path());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_NE(one.output.find("decimated to"), std::string::npos) << one.output;
  expect_success(
      "extract stack -t 100 -q -o three.ply --image three.png --decimate 0.2 "
      "--threads 3 --slab-slices 4",
      dir);
  EXPECT_EQ(test::read_file_bytes(dir / "three.ply"), test::read_file_bytes(dir / "one.ply"));
  EXPECT_EQ(test::read_file_bytes(dir / "three.png"), test::read_file_bytes(dir / "one.png"));
  // Shaded flat: gradients would be read from slices long gone.
  expect_success("extract stack -t 100 -q --image flat.png --flat --decimate 0.2", dir);
  EXPECT_EQ(test::read_file_bytes(dir / "flat.png"), test::read_file_bytes(dir / "one.png"));
  expect_success("extract stack -t 100 -q --image full.png --flat", dir);
  EXPECT_NE(test::read_file_bytes(dir / "one.png"), test::read_file_bytes(dir / "full.png"));
}

TEST(DecimateCli, WhatItCannotDoIsRefusedInOneLine) {
  ScratchDirectory dir;
  make_stack(dir);
  for (const char* arguments :
       {"--decimate 0", "--decimate 1.5", "--decimate x", "--max-error 0", "--max-error -1"}) {
    const auto result =
        run_mvox(std::string("extract stack -t 100 -o x.ply ") + arguments, dir.path());
    EXPECT_EQ(result.exit_code, 2) << arguments << ": " << result.output;
  }
  if (decimation_available()) {
    const auto normals =
        run_mvox("extract stack -t 100 -o x.ply --decimate 0.2 --normals", dir.path());
    EXPECT_EQ(normals.exit_code, 2) << normals.output;
    EXPECT_NE(normals.output.find("--normals"), std::string::npos) << normals.output;
  }
  EXPECT_EQ(dir.listing(), "stack ");
}

}  // namespace
}  // namespace mvox
