#include "write/mesh/world_transform.h"

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

std::string usable_range(double lowest, double highest) {
  return " (usable: " + number(lowest) + " to " + number(highest) + ")";
}

}  // namespace

std::string spacing_problem(double value, const std::string& shown) {
  const std::string text = shown.empty() ? number(value) : shown;
  if (!(value > 0.0) || !std::isfinite(value)) return "must be positive and finite, got " + text;
  if (value < kMinSpacing)
    return "is too small for float coordinates, got " + text +
           usable_range(kMinSpacing, kMaxCoordinate);
  if (value > kMaxCoordinate)
    return "is too large for float coordinates, got " + text +
           usable_range(kMinSpacing, kMaxCoordinate);
  return "";
}

std::string origin_problem(double value, const std::string& shown) {
  const std::string text = shown.empty() ? number(value) : shown;
  if (!std::isfinite(value)) return "must be finite, got " + text;
  if (std::fabs(value) > kMaxCoordinate)
    return "is too large for float coordinates, got " + text +
           usable_range(-kMaxCoordinate, kMaxCoordinate);
  return "";
}

WorldTransform WorldTransform::of_volume(const VolumeInfo& volume) {
  WorldTransform transform;
  for (int a = 0; a < 3; ++a) {
    transform.origin[a] = volume.origin[a];
    transform.spacing[a] = volume.spacing[a];
    for (int i = 0; i < 3; ++i) transform.axes[a][i] = volume.axes[a][i];
  }
  return transform;
}

void WorldTransform::check(const std::string& subject) const {
  for (int a = 0; a < 3; ++a) {
    const std::string spacing_text = spacing_problem(spacing[a]);
    if (!spacing_text.empty())
      throw Error(subject, std::string("spacing ") + kAxisName[a] + " " + spacing_text);
    const std::string origin_text = origin_problem(origin[a]);
    if (!origin_text.empty())
      throw Error(subject, std::string("origin ") + kAxisName[a] + " " + origin_text);
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(axes[a][i]))
        throw Error(subject, std::string("voxel axis ") + kAxisName[a] +
                                 " direction must be finite, got " + number(axes[a][i]));
  }
  if (!axes_span_space())
    throw Error(subject, "voxel axes are zero or coplanar, so they cannot place a mesh");
}

bool WorldTransform::axes_span_space() const {
  // The determinant relative to the axes' lengths is the volume of the parallelepiped they span
  // as a fraction of a cube's: near 0 the axes are (nearly) coplanar and the mesh would be
  // flattened.
  const double scale = length(axes[0]) * length(axes[1]) * length(axes[2]);
  return scale > 0.0 && std::fabs(determinant(axes)) > 1e-6 * scale;
}

std::string WorldTransform::reach_problem(std::uint32_t width, std::uint32_t height,
                                          std::uint32_t depth) const {
  // Each world coordinate is affine in the voxel position, so its extremes are at the corners
  // of the box the vertices lie in.
  const double last[3] = {double(width) - 0.5, double(height) - 0.5, double(depth) - 0.5};
  double farthest[3] = {0.0, 0.0, 0.0};
  for (int corner = 0; corner < 8; ++corner) {
    const Vector3d p = position(static_cast<float>((corner & 1) ? last[0] : -0.5),
                                static_cast<float>((corner & 2) ? last[1] : -0.5),
                                static_cast<float>((corner & 4) ? last[2] : -0.5));
    for (int i = 0; i < 3; ++i)
      if (std::fabs(p[i]) > std::fabs(farthest[i])) farthest[i] = p[i];
  }
  for (int i = 0; i < 3; ++i)
    if (!(std::fabs(farthest[i]) <= kMaxCoordinate))
      return "the mesh would reach " + number(farthest[i]) + " along " + kAxisName[i] +
             ", beyond float's range (at most " + number(kMaxCoordinate) + ")";
  return "";
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
