#include "random_phantoms.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "splitmix64.h"

namespace mvox::sim {
namespace {

constexpr double kCutoffScaledDistanceSquared = 25;  // (5 radii)^2, see RandomBlobs::density

}  // namespace

RandomBlobs::RandomBlobs(Grid grid, std::uint64_t seed, std::uint32_t blob_count) : grid_(grid) {
  check_grid(grid, "blobs");
  const double radius_max = std::max(1.0, 0.1 * min_dimension(grid));
  const double radius_min = std::min(2.0, radius_max / 2);
  std::uint64_t state = seed;
  // Draws in a fixed order (x, y, z, radius, amplitude), one output each, so that the
  // parameters are a pure function of the seed.
  auto uniform = [&state](double lo, double hi) {
    return lo + (hi - lo) * unit_interval(splitmix64_next(state));
  };
  auto along = [&uniform](std::uint32_t size) {
    return uniform(0.1 * (size - 1.0), 0.9 * (size - 1.0));
  };
  blobs_.reserve(blob_count);
  inv_radius_squared_.reserve(blob_count);
  for (std::uint32_t i = 0; i < blob_count; ++i) {
    Blob blob;
    blob.centre.x = along(grid.width);
    blob.centre.y = along(grid.height);
    blob.centre.z = along(grid.depth);
    blob.radius = uniform(radius_min, radius_max);
    blob.amplitude = uniform(0.6, 1.4);
    blobs_.push_back(blob);
    inv_radius_squared_.push_back(1.0 / (blob.radius * blob.radius));
  }
  // Index the blobs by the slices they reach, so a voxel only visits the few blobs near its
  // slice instead of all of them; the per-voxel cutoff test still decides, so the densities
  // are the same as without the index.
  slice_blob_begin_.reserve(std::size_t{grid.depth} + 1);
  for (std::uint32_t z = 0; z < grid.depth; ++z) {
    slice_blob_begin_.push_back(static_cast<std::uint32_t>(slice_blobs_.size()));
    for (std::uint32_t i = 0; i < blob_count; ++i) {
      const double dz = z - blobs_[i].centre.z;
      if (dz * dz * inv_radius_squared_[i] < kCutoffScaledDistanceSquared) {
        slice_blobs_.push_back(i);
      }
    }
  }
  slice_blob_begin_.push_back(static_cast<std::uint32_t>(slice_blobs_.size()));
}

float RandomBlobs::density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  // std::exp2 may differ in the last bit between C libraries; the blob parameters, which carry
  // the randomness, do not.
  double sum = 0;
  for (std::uint32_t k = slice_blob_begin_[z]; k < slice_blob_begin_[z + 1]; ++k) {
    const std::uint32_t i = slice_blobs_[k];
    const Point3& c = blobs_[i].centre;
    const double dx = x - c.x;
    const double dy = y - c.y;
    const double dz = z - c.z;
    const double scaled = (dx * dx + dy * dy + dz * dz) * inv_radius_squared_[i];
    // Beyond 5 radii a blob adds less than 2^-25 (3e-8) of its amplitude: leaving those tails
    // out is part of the phantom's definition and saves most of the exp2 calls.
    if (scaled < kCutoffScaledDistanceSquared) sum += blobs_[i].amplitude * std::exp2(-scaled);
  }
  return static_cast<float>(sum);
}

RandomVoxels::RandomVoxels(Grid grid, std::uint64_t seed, double inner_probability)
    : grid_(grid), seed_(seed), inner_probability_(inner_probability) {
  check_grid(grid, "random");
  if (!(inner_probability >= 0 && inner_probability <= 1)) {
    throw std::invalid_argument("random: inner probability must be in [0, 1], got " +
                                std::to_string(inner_probability));
  }
}

float RandomVoxels::density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
  // unit_interval is < 1, so probability 1 fills every voxel and 0 none.
  return unit_interval(voxel_hash(seed_, x, y, z)) < inner_probability_ ? 1.0f : 0.0f;
}

}  // namespace mvox::sim
