#pragma once
// Binary analytic shapes with known volume and topology: the phantoms whose surfaces tests can
// predict exactly (a sphere has Euler characteristic 2, a torus 0, a hollow shell two surfaces).
// All sizes are in voxel units; a voxel is inside when its centre is (boundary included).
#include <vector>

#include "phantom.h"

namespace mvox::sim {

// Density 1 where the distance to `centre` is <= `radius`, else 0.
class Sphere final : public Phantom {
 public:
  // Throws std::invalid_argument for an empty grid or a negative or non-finite radius.
  Sphere(Grid grid, Point3 centre, double radius);
  Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override;
  float partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                               double psf_sigma) const override;
  const char* name() const override { return "sphere"; }

 private:
  Grid grid_;
  Point3 centre_;
  double radius_squared_;
};

// Density 1 inside a ring torus whose axis is parallel to z through `centre`: the points within
// `minor_radius` of the circle of `major_radius` around the axis in the plane z = centre.z.
class Torus final : public Phantom {
 public:
  // Throws std::invalid_argument for an empty grid or negative or non-finite radii.
  Torus(Grid grid, Point3 centre, double major_radius, double minor_radius);
  Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override;
  float partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                               double psf_sigma) const override;
  const char* name() const override { return "torus"; }

 private:
  Grid grid_;
  Point3 centre_;
  double major_radius_;
  double minor_radius_squared_;
};

// Concentric shells around `centre`. `radii` r0 > r1 > r2 > ... alternate solid and empty going
// inward: density 1 for r1 < d <= r0, 0 for r2 < d <= r1, 1 for r3 < d <= r2, and so on (d is
// the distance to the centre). Two radii make one hollow shell; an odd count ends in a ball.
class NestedShells final : public Phantom {
 public:
  // Throws std::invalid_argument for an empty grid, no radii, or radii that are not finite,
  // non-negative and strictly decreasing.
  NestedShells(Grid grid, Point3 centre, std::vector<double> radii);
  Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override;
  float partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                               double psf_sigma) const override;
  const char* name() const override { return "shells"; }

 private:
  Grid grid_;
  Point3 centre_;
  std::vector<double> radii_squared_;  // decreasing
};

}  // namespace mvox::sim
