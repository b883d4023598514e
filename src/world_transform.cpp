#include "world_transform.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "error.h"

namespace mvox {
namespace {

const char* const kAxisName[3] = {"x", "y", "z"};

double determinant(const Matrix3d& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

double length(const Vector3d& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

}  // namespace

WorldTransform WorldTransform::of_volume(const VolumeInfo& volume) {
  WorldTransform transform;
  for (int a = 0; a < 3; ++a) {
    transform.origin[a] = volume.origin[a];
    transform.spacing[a] = volume.spacing[a];
    for (int i = 0; i < 3; ++i) transform.axes[a][i] = volume.axes[a][i];
  }
  return transform;
}

void WorldTransform::check() const {
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  for (int a = 0; a < 3; ++a) {
    if (!(spacing[a] > 0.0 && spacing[a] <= kFloatMax))
      throw Error(std::string("spacing ") + kAxisName[a],
                  "must be positive and finite, got " + number(spacing[a]));
    if (!(std::fabs(origin[a]) <= kFloatMax))
      throw Error(std::string("origin ") + kAxisName[a],
                  "must be finite, got " + number(origin[a]));
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(axes[a][i]))
        throw Error(std::string("voxel axis ") + kAxisName[a],
                    "direction must be finite, got " + number(axes[a][i]));
  }
  // The determinant relative to the axes' lengths is the volume of the parallelepiped they span
  // as a fraction of a cube's: near 0 the axes are (nearly) coplanar and the mesh would be
  // flattened.
  const double scale = length(axes[0]) * length(axes[1]) * length(axes[2]);
  if (!(scale > 0.0) || !(std::fabs(determinant(axes)) > 1e-6 * scale))
    throw Error("voxel axes", "directions are zero or coplanar, so they cannot place a mesh");
}

bool WorldTransform::is_axis_aligned() const {
  const Matrix3d identity = WorldTransform{}.axes;
  return axes == identity;
}

bool WorldTransform::mirrors() const {
  // Spacing is positive, so the sign of the whole transform is that of the axes.
  return determinant(axes) < 0.0;
}

Matrix3d WorldTransform::normal_matrix() const {
  // A has the axes as columns: A[i][a] = axes[a][i]. Its inverse transpose is the cofactor
  // matrix over the determinant; the cofactors of A's column a are the cross product of the two
  // other columns.
  const double det = determinant(axes);
  Matrix3d m{};
  for (int a = 0; a < 3; ++a) {
    const Vector3d& u = axes[(a + 1) % 3];
    const Vector3d& w = axes[(a + 2) % 3];
    const Vector3d cross = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                            u[0] * w[1] - u[1] * w[0]};
    // Column a of the inverse transpose.
    for (int i = 0; i < 3; ++i) m[i][a] = cross[i] / det;
  }
  return m;
}

glm::vec3 world_normal(const Matrix3d& normal_matrix, const glm::vec3& normal) {
  Vector3d world = {0.0, 0.0, 0.0};
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) world[i] += normal_matrix[i][a] * normal[a];
  const double size = length(world);
  if (!(size > 0.0)) return glm::vec3(0.0f);
  return glm::vec3(static_cast<float>(world[0] / size), static_cast<float>(world[1] / size),
                   static_cast<float>(world[2] / size));
}

}  // namespace mvox
