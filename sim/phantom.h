#pragma once
// What a simulated volume is: a density defined at every voxel centre of a grid, evaluated on
// demand so that a scanner can produce any slice on its own without ever holding the volume.
#include <cmath>
#include <cstdint>
#include <vector>

namespace mvox::sim {

// The voxel lattice a phantom is sampled on.
struct Grid {
  std::uint32_t width = 0;   // voxels along x (columns)
  std::uint32_t height = 0;  // voxels along y (rows)
  std::uint32_t depth = 0;   // voxels along z (slices)
};

// A point in voxel units: the centre of voxel (x, y, z) is the point (x, y, z).
struct Point3 {
  double x = 0;
  double y = 0;
  double z = 0;
};

class Phantom {
 public:
  virtual ~Phantom() = default;
  virtual Grid grid() const = 0;
  // Density at the centre of voxel (x, y, z); requires x < width, y < height, z < depth.
  // Typically 0 outside the object and about 1 inside. Deterministic: the same voxel always
  // gives the same value, whatever was evaluated before, so slices can be made in any order.
  virtual float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const = 0;
  // density() as a real scan records it: each boundary of an analytic shape becomes a linear
  // ramp one voxel wide, centred on the boundary (the partial-volume effect), blurred by a
  // Gaussian point-spread function of `psf_sigma` voxels (0: none), so gradients carry the
  // surface's sub-voxel position and direction. Where density() steps from a to b, this passes
  // (a + b) / 2 exactly on the boundary: thresholding a single step there gives the voxels
  // density() gives. Phantoms made of voxels have no finer edge and return density().
  virtual float partial_volume_density(std::uint32_t x, std::uint32_t y, std::uint32_t z,
                                       double psf_sigma) const {
    (void)psf_sigma;
    return density(x, y, z);
  }
  // The factory name of the phantom family ("sphere", "shepp-logan", ...); static storage.
  virtual const char* name() const = 0;
};

// The fraction of a voxel's density whose centre lies `inside` voxels within a boundary
// (negative: outside), 1/2 on the boundary: a ramp from 0 to 1 over one voxel, convolved with a
// Gaussian of `psf_sigma` voxels when that is > 0. The convolution in closed form:
// the integral of the Gaussian's CDF Phi(t / sigma) from inside - 1/2 to inside + 1/2.
inline float boundary_ramp(double inside, double psf_sigma) {
  if (!(psf_sigma > 0.0))
    return inside >= 0.5 ? 1.0f : inside <= -0.5 ? 0.0f : static_cast<float>(0.5 + inside);
  const double reach = 0.5 + 6.0 * psf_sigma;  // beyond: within 1e-9 of 0 or 1
  if (inside >= reach) return 1.0f;
  if (inside <= -reach) return 0.0f;
  // An antiderivative of Phi(x / sigma): x Phi(x / sigma) + sigma phi(x / sigma).
  auto integral = [psf_sigma](double x) {
    const double s = x / psf_sigma;
    return x * 0.5 * std::erfc(-s * 0.70710678118654752440) +
           psf_sigma * 0.39894228040143267794 * std::exp(-0.5 * s * s);
  };
  return static_cast<float>(integral(inside + 0.5) - integral(inside - 0.5));
}

// How far from a boundary boundary_ramp() is neither 0 nor 1, in voxels.
inline double boundary_reach(double psf_sigma) {
  return psf_sigma > 0.0 ? 0.5 + 6.0 * psf_sigma : 0.5;
}

// The centre of the grid in voxel units, ((width - 1) / 2, (height - 1) / 2, (depth - 1) / 2):
// a shape placed there gives a voxel pattern that is mirror-symmetric on every axis.
Point3 grid_centre(const Grid& grid);

// The smallest of width, height and depth.
std::uint32_t min_dimension(const Grid& grid);

// Throws std::invalid_argument naming `phantom_name` when a dimension of `grid` is 0.
void check_grid(const Grid& grid, const char* phantom_name);

// Every density of `phantom`, x fastest, then y, then z: voxel (x, y, z) is at index
// x + width * (y + height * z). Holds the whole volume, so it is meant for tests and small grids.
std::vector<float> sample_volume(const Phantom& phantom);

}  // namespace mvox::sim
