#include "cli_mesh_checks.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>

#include "mesh_topology.h"
#include "ply_mesh.h"

namespace mvox::test {

void make_phantom_stack(const ScratchDirectory& dir, const std::string& name,
                        const std::string& size) {
  const auto written = run_mvox("phantom " + name + " -o stack --size " + size + " -q", dir.path());
  ASSERT_EQ(written.exit_code, 0) << written.output;
}

void expect_success(const std::string& arguments, const ScratchDirectory& dir) {
  const auto result = run_mvox(arguments, dir.path());
  EXPECT_EQ(result.exit_code, 0) << arguments << "\n" << result.output;
}

std::size_t vertices_moved_along_edges(const PlyMesh& plain, const PlyMesh& moved, float limit) {
  EXPECT_EQ(moved.vertex_count(), plain.vertex_count());
  if (moved.vertex_count() != plain.vertex_count()) return 0;
  std::size_t changed = 0;
  for (std::size_t i = 0; i < moved.vertex_count(); ++i) {
    int axes = 0;
    for (int a = 0; a < 3; ++a) {
      const float shift = moved.positions[i][a] - plain.positions[i][a];
      EXPECT_LT(std::fabs(shift), limit) << "vertex " << i;
      axes += shift != 0.0f;
    }
    EXPECT_LE(axes, 1) << "vertex " << i << " left its edge";
    if (axes > 1) return changed;
    changed += static_cast<std::size_t>(axes);
  }
  return changed;
}

void expect_engines_faces_with_moved_vertices(const PlyMesh& plain, const PlyMesh& moved) {
  ASSERT_GT(moved.face_count(), 500u);
  EXPECT_EQ(moved.face_offsets, plain.face_offsets);
  EXPECT_EQ(moved.face_indices, plain.face_indices);
  EXPECT_GT(vertices_moved_along_edges(plain, moved, 0.5f), moved.vertex_count() / 2);
  const Topology topology = analyse(to_mesh(moved));
  EXPECT_TRUE(topology.closed_and_consistent()) << describe(topology);
}

StlFile expect_corners_among(const std::string& path, const PlyMesh& mesh) {
  const StlFile stl = read_stl(path);
  const std::set<std::array<float, 3>> corners(mesh.positions.begin(), mesh.positions.end());
  for (const StlTriangle& triangle : stl.triangles)
    for (const auto& corner : triangle.vertices) {
      EXPECT_EQ(corners.count({corner[0], corner[1], corner[2]}), 1u);
      if (corners.count({corner[0], corner[1], corner[2]}) != 1) return stl;
    }
  return stl;
}

}  // namespace mvox::test
