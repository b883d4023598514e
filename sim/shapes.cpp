#include "shapes.h"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace mvox::sim {
namespace {

double distance_squared(const Point3& centre, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  const double dx = x - centre.x;
  const double dy = y - centre.y;
  const double dz = z - centre.z;
  return dx * dx + dy * dy + dz * dz;
}

void check_radius(double radius, const char* phantom_name, const char* what) {
  // Written as a negated comparison so that NaN is refused too.
  if (!(radius >= 0) || !std::isfinite(radius)) {
    throw std::invalid_argument(std::string(phantom_name) + ": " + what +
                                " must be finite and >= 0, got " + std::to_string(radius));
  }
}

}  // namespace

Sphere::Sphere(Grid grid, Point3 centre, double radius)
    : grid_(grid), centre_(centre), radius_squared_(radius * radius) {
  check_grid(grid, "sphere");
  check_radius(radius, "sphere", "radius");
}

float Sphere::density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  return distance_squared(centre_, x, y, z) <= radius_squared_ ? 1.0f : 0.0f;
}

float Sphere::partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                                     double psf_sigma) const {
  return boundary_ramp(std::sqrt(radius_squared_) - std::sqrt(distance_squared(centre_, x, y, z)),
                       psf_sigma);
}

Torus::Torus(Grid grid, Point3 centre, double major_radius, double minor_radius)
    : grid_(grid),
      centre_(centre),
      major_radius_(major_radius),
      minor_radius_squared_(minor_radius * minor_radius) {
  check_grid(grid, "torus");
  check_radius(major_radius, "torus", "major radius");
  check_radius(minor_radius, "torus", "minor radius");
}

float Torus::density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  const double dx = x - centre_.x;
  const double dy = y - centre_.y;
  const double dz = z - centre_.z;
  const double from_ring = std::sqrt(dx * dx + dy * dy) - major_radius_;
  return from_ring * from_ring + dz * dz <= minor_radius_squared_ ? 1.0f : 0.0f;
}

float Torus::partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                                    double psf_sigma) const {
  const double dx = x - centre_.x;
  const double dy = y - centre_.y;
  const double dz = z - centre_.z;
  const double from_ring = std::sqrt(dx * dx + dy * dy) - major_radius_;
  return boundary_ramp(std::sqrt(minor_radius_squared_) -
                       std::sqrt(from_ring * from_ring + dz * dz), psf_sigma);
}

NestedShells::NestedShells(Grid grid, Point3 centre, std::vector<double> radii)
    : grid_(grid), centre_(centre) {
  check_grid(grid, "shells");
  if (radii.empty()) throw std::invalid_argument("shells: at least one radius is needed");
  for (std::size_t i = 0; i < radii.size(); ++i) {
    check_radius(radii[i], "shells", "every radius");
    if (i > 0 && !(radii[i] < radii[i - 1])) {
      throw std::invalid_argument("shells: radii must be strictly decreasing, got " +
                                  std::to_string(radii[i - 1]) + " then " +
                                  std::to_string(radii[i]));
    }
  }
  radii_squared_.reserve(radii.size());
  for (double radius : radii) radii_squared_.push_back(radius * radius);
}

float NestedShells::density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  // The number of spheres that contain the point decides: inside the outermost only (1) is
  // solid, inside two is the first hollow, and so on.
  const double d2 = distance_squared(centre_, x, y, z);
  std::size_t containing = 0;
  while (containing < radii_squared_.size() && d2 <= radii_squared_[containing]) ++containing;
  return containing % 2 == 1 ? 1.0f : 0.0f;
}

float NestedShells::partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                                           double psf_sigma) const {
  // Inside the outermost sphere adds 1, inside the next takes it away, and so on: the same
  // alternation as density(), each boundary ramped.
  const double d = std::sqrt(distance_squared(centre_, x, y, z));
  float sum = 0.0f;
  for (std::size_t i = 0; i < radii_squared_.size(); ++i) {
    const float ramp = boundary_ramp(std::sqrt(radii_squared_[i]) - d, psf_sigma);
    sum += i % 2 == 0 ? ramp : -ramp;
  }
  return sum;
}

}  // namespace mvox::sim
