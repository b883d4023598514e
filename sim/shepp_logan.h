#pragma once
// The 3-D modified Shepp-Logan head phantom: ten ellipsoids whose densities add up, the standard
// test object of tomography. Its skull, ventricles and small "tumours" give nested surfaces with
// several components at one threshold.
#include "phantom.h"

namespace mvox::sim {

// One ellipsoid of the table, in normalised coordinates: the phantom spans [-1, 1] on each axis.
struct SheppLoganEllipsoid {
  double intensity;  // added to the density inside the ellipsoid
  double semi_axis_x, semi_axis_y, semi_axis_z;
  double centre_x, centre_y, centre_z;
  double rotation_z_degrees;  // counter-clockwise about z, seen with y pointing up
};

constexpr int kSheppLoganEllipsoidCount = 10;

// The table the phantom is built from (see shepp_logan.cpp for where it comes from).
const SheppLoganEllipsoid* shepp_logan_ellipsoids();

// The phantom sampled on `grid`. [-1, 1] is stretched over each axis separately: voxel centre x
// is at (2x + 1) / width - 1, slice z at (2z + 1) / depth - 1, and row y at
// 1 - (2y + 1) / height. Rows run downwards, so the table's y points up the image: an axial
// slice shown with row 0 at the top looks like the familiar 2-D Shepp-Logan picture (the three
// small ellipses at the bottom, the thicker part of the skull at the top).
class SheppLogan3D final : public Phantom {
 public:
  // Throws std::invalid_argument for an empty grid.
  explicit SheppLogan3D(Grid grid);
  Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override;
  // Each ellipsoid's intensity times its ramp; the distance to an ellipsoid's surface is taken
  // along the ray from its centre (exact for spheres, close for these gentle ellipsoids).
  float partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                               double psf_sigma) const override;
  const char* name() const override { return "shepp-logan"; }

 private:
  struct Prepared {
    double intensity;
    double inv_axis_x, inv_axis_y, inv_axis_z;
    double centre_x, centre_y, centre_z;
    double cos_rotation, sin_rotation;
    double smallest_semi_axis_voxels;  // partial_volume_density()'s early exit
  };
  Grid grid_;
  Prepared ellipsoids_[kSheppLoganEllipsoidCount];
};

}  // namespace mvox::sim
