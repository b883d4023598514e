#pragma once
// Where a mesh lands in the world: the one placement every mesh writer applies to the engine's
// voxel coordinates (DESIGN.md section 4), from the input's VolumeInfo or the user's --spacing
// and --origin.
#include <array>
#include <glm/vec3.hpp>

#include "mvox/slice_source.h"

namespace mvox {

using Vector3d = std::array<double, 3>;
using Matrix3d = std::array<Vector3d, 3>;  // row-major: m[row][column]

struct WorldTransform {
  // world = origin + sum over a of axes[a] * spacing[a] * v[a], for a voxel position v (x =
  // column, y = row, z = slice), in double and rounded to float when written. axes[a] is the
  // world direction of increasing voxel coordinate a, as VolumeInfo::axes.
  Vector3d origin = {0.0, 0.0, 0.0};
  Vector3d spacing = {1.0, 1.0, 1.0};
  Matrix3d axes = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};

  static WorldTransform of_volume(const VolumeInfo& volume);

  // Throws mvox::Error when a value cannot place a mesh: a spacing that is not positive and
  // finite (a negative one would mirror silently; mirroring belongs to the axes), an origin or
  // axis component that is not finite or beyond float range, or axes that do not span space.
  void check() const;

  bool is_axis_aligned() const;  // axes are the identity: positions only scale and shift
  // True when the transform turns right-handed into left-handed (its determinant is negative):
  // faces wound counter-clockwise seen from outside in voxel space would be clockwise in the
  // world, so writers reverse them.
  bool mirrors() const;

  // The world position of voxel position (x, y, z), in double.
  Vector3d position(float x, float y, float z) const {
    const double v[3] = {x, y, z};
    Vector3d world = origin;
    // Summed per axis so that, with identity axes, each coordinate is exactly origin + spacing *
    // v (the added zeros change nothing): what the writers wrote before axes existed.
    for (int a = 0; a < 3; ++a) {
      const double step = spacing[a] * v[a];
      for (int i = 0; i < 3; ++i) world[i] += axes[a][i] * step;
    }
    return world;
  }

  // position() for identity axes, with the same result: origin + spacing * v per axis. The
  // writers' hot path, since most inputs have no orientation.
  Vector3d axis_aligned_position(float x, float y, float z) const {
    return {origin[0] + spacing[0] * x, origin[1] + spacing[1] * y, origin[2] + spacing[2] * z};
  }

  // The matrix that takes a normal from the spaced voxel frame (the gradient per world unit
  // along the voxel axes, as VertexNormals computes it) to the world: the inverse transpose of
  // the matrix whose columns are the axes. For orthonormal axes that is the rotation itself.
  // Requires check() to pass.
  Matrix3d normal_matrix() const;
};

// `normal` (a unit vector in the spaced voxel frame) in the world, as a unit vector, through a
// matrix from WorldTransform::normal_matrix(). A zero normal stays zero.
glm::vec3 world_normal(const Matrix3d& normal_matrix, const glm::vec3& normal);

}  // namespace mvox
