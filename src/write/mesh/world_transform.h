#pragma once
// Where a mesh lands in the world: the one placement every mesh writer applies to the engine's
// voxel coordinates (docs/design.md section 4), from the input's VolumeInfo or the user's --spacing
// and --origin.
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <string>

#include "mvox/slice_source.h"

namespace mvox {

using Vector3d = std::array<double, 3>;

// The values a placement may hold, because meshes are written in float. A spacing must keep half
// of itself (the smallest step between two vertices) a normal float: below that, coordinates
// lose bits one by one, and from about 1e-45 on they all round to 0. No coordinate may pass
// float's largest value.
inline constexpr double kMinSpacing = 2.0 * std::numeric_limits<float>::min();  // 2.35e-38
inline constexpr double kMaxCoordinate = std::numeric_limits<float>::max();     // 3.40e+38

// Why `value` cannot be a spacing, or "" when it can: "must be positive and finite, got 0", "is
// too small for float coordinates, got 1e-40 (usable: 2.35099e-38 to 3.40282e+38)", "is too
// large ...". `shown` is the value as the user wrote it, or empty to print it with %g.
std::string spacing_problem(double value, const std::string& shown = "");
// The same for a coordinate of the origin: "must be finite, got nan", "is too large ...".
std::string origin_problem(double value, const std::string& shown = "");

using Matrix3d = std::array<Vector3d, 3>;  // row-major: m[row][column]

struct WorldTransform {
  // world = origin + sum over a of axes[a] * spacing[a] * v[a], for a voxel position v (x =
  // column, y = row, z = slice), in double and rounded to float when written. axes[a] is the
  // world direction of increasing voxel coordinate a, as VolumeInfo::axes.
  Vector3d origin = {0.0, 0.0, 0.0};
  Vector3d spacing = {1.0, 1.0, 1.0};
  Matrix3d axes = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};

  static WorldTransform of_volume(const VolumeInfo& volume);

  // Throws mvox::Error(subject, ...) when a value cannot place a mesh: a spacing outside
  // spacing_problem()'s range (a negative one would mirror silently; mirroring belongs to the
  // axes), an origin outside origin_problem()'s, an axis component that is not finite, or axes
  // that do not span space. `subject` is what gave the values: the input file, as a rule. The
  // problem names the value, e.g. "spacing x is too large for float coordinates, got 1e+300
  // (usable: ...)".
  void check(const std::string& subject) const;

  // Why the vertices of a width x height x depth volume placed by this transform would not all
  // fit in float coordinates ("the mesh would reach 3.7e+38 along z, beyond float's range (at
  // most 3.40282e+38)"), or "" when they fit. Vertices lie from -0.5 to size - 0.5 voxels along
  // each axis. Requires check() to pass.
  std::string reach_problem(std::uint32_t width, std::uint32_t height, std::uint32_t depth) const;

  // True when the axes span space: no axis is zero and they are not (nearly) coplanar.
  bool axes_span_space() const;

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
