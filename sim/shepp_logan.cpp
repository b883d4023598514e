#include "shepp_logan.h"

#include <algorithm>
#include <cmath>

namespace mvox::sim {
namespace {

// The 3-D modified Shepp-Logan table as widely published: P. A. Toft, "The Radon Transform:
// Theory and Implementation", PhD thesis, DTU 1996, pp. 199-200 (the "modified" intensities with
// better contrast than Shepp and Logan's 1974 originals), extended to 3-D with the semi-axes and
// centres along z of M. Schabel's "3D Shepp-Logan phantom" (MATLAB Central File Exchange 9416),
// the table most 3-D implementations copy. Rows 3 and 4 use the 2-D angles -18 and +18 degrees
// about z; Schabel's table also lists a third Euler angle psi = 10 for them, which with
// theta = 0 is one more turn about z (-8 and 28 degrees in all). We leave it out so that axial
// slices match the familiar 2-D phantom.
// clang-format off
constexpr SheppLoganEllipsoid kModifiedSheppLogan[kSheppLoganEllipsoidCount] = {
    // intensity  a       b      c      x0     y0       z0     phi
    { 1.0,        0.6900, 0.920, 0.810,  0.00,  0.0000,  0.00,   0},  // skull (outer surface)
    {-0.8,        0.6624, 0.874, 0.780,  0.00, -0.0184,  0.00,   0},  // brain (skull inner surface)
    {-0.2,        0.1100, 0.310, 0.220,  0.22,  0.0000,  0.00, -18},  // ventricle at +x
    {-0.2,        0.1600, 0.410, 0.280, -0.22,  0.0000,  0.00,  18},  // ventricle at -x
    { 0.1,        0.2100, 0.250, 0.410,  0.00,  0.3500, -0.15,   0},  // large upper ellipse
    { 0.1,        0.0460, 0.046, 0.050,  0.00,  0.1000,  0.25,   0},
    { 0.1,        0.0460, 0.046, 0.050,  0.00, -0.1000,  0.25,   0},
    { 0.1,        0.0460, 0.023, 0.050, -0.08, -0.6050,  0.00,   0},  // the three small lower ones
    { 0.1,        0.0230, 0.023, 0.020,  0.00, -0.6060,  0.00,   0},
    { 0.1,        0.0230, 0.046, 0.020,  0.06, -0.6050,  0.00,   0},
};
// clang-format on

constexpr double kPi = 3.14159265358979323846;

// Voxel index -> normalised coordinate of its centre, so that the grid spans [-1, 1] exactly.
double normalised(std::uint32_t index, std::uint32_t count) {
  return (2.0 * index + 1.0) / count - 1.0;
}

}  // namespace

const SheppLoganEllipsoid* shepp_logan_ellipsoids() { return kModifiedSheppLogan; }

SheppLogan3D::SheppLogan3D(Grid grid) : grid_(grid) {
  check_grid(grid, "shepp-logan");
  for (int i = 0; i < kSheppLoganEllipsoidCount; ++i) {
    const SheppLoganEllipsoid& e = kModifiedSheppLogan[i];
    const double angle = e.rotation_z_degrees * kPi / 180.0;
    // In voxels, a lower bound whatever the turn about z (the x and y voxel sizes may differ).
    const double coarsest_xy = 2.0 / std::min(grid.width, grid.height);
    const double smallest_semi_axis_voxels =
        std::min(std::min(e.semi_axis_x, e.semi_axis_y) / coarsest_xy,
                 e.semi_axis_z * grid.depth / 2.0);
    ellipsoids_[i] = {e.intensity,         1.0 / e.semi_axis_x, 1.0 / e.semi_axis_y,
                      1.0 / e.semi_axis_z, e.centre_x,          e.centre_y,
                      e.centre_z,          std::cos(angle),     std::sin(angle),
                      smallest_semi_axis_voxels};
  }
}

float SheppLogan3D::density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  const double px = normalised(x, grid_.width);
  const double py = -normalised(y, grid_.height);  // rows run down, the table's y runs up
  const double pz = normalised(z, grid_.depth);
  double sum = 0;
  for (const Prepared& e : ellipsoids_) {
    const double dx = px - e.centre_x;
    const double dy = py - e.centre_y;
    // Rotate the point by -angle into the ellipsoid's own axes (same convention as the 2-D
    // phantom, so a positive angle turns the ellipsoid counter-clockwise).
    const double u = (dx * e.cos_rotation + dy * e.sin_rotation) * e.inv_axis_x;
    const double v = (dy * e.cos_rotation - dx * e.sin_rotation) * e.inv_axis_y;
    const double w = (pz - e.centre_z) * e.inv_axis_z;
    if (u * u + v * v + w * w <= 1.0) sum += e.intensity;
  }
  return static_cast<float>(sum);
}

float SheppLogan3D::partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                                           double psf_sigma) const {
  const double px = normalised(x, grid_.width);
  const double py = -normalised(y, grid_.height);
  const double pz = normalised(z, grid_.depth);
  // Normalised units per voxel along each axis (the grid spans 2 units).
  const double voxel_x = 2.0 / grid_.width, voxel_y = 2.0 / grid_.height;
  const double voxel_z = 2.0 / grid_.depth;
  double sum = 0;
  for (const Prepared& e : ellipsoids_) {
    const double dx = px - e.centre_x;
    const double dy = py - e.centre_y;
    const double dz = pz - e.centre_z;
    const double u = (dx * e.cos_rotation + dy * e.sin_rotation) * e.inv_axis_x;
    const double v = (dy * e.cos_rotation - dx * e.sin_rotation) * e.inv_axis_y;
    const double w = dz * e.inv_axis_z;
    const double q = std::sqrt(u * u + v * v + w * w);  // 1 on the surface
    // Far outside: the point is at least q times the smallest semi-axis from the centre, so for
    // q >= 2 the surface is at least that far away; nothing to add once it is past the ramp.
    if (q >= 2.0 && q * e.smallest_semi_axis_voxels >= 2.0 * boundary_reach(psf_sigma)) continue;
    // From the centre to the point in voxels; the surface lies at that length / q.
    const double length =
        std::sqrt((dx / voxel_x) * (dx / voxel_x) + (dy / voxel_y) * (dy / voxel_y) +
                  (dz / voxel_z) * (dz / voxel_z));
    const double inside = q > 0.0 ? length * (1.0 / q - 1.0) : 1.0;
    sum += e.intensity * boundary_ramp(inside, psf_sigma);
  }
  return static_cast<float>(sum);
}

}  // namespace mvox::sim
