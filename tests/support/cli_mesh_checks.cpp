#include "cli_mesh_checks.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace mvox::test
