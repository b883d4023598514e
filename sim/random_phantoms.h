#pragma once
// Seeded random phantoms: smooth blobs with irregular topology, and independent random voxels
// (the worst case for a surface extractor: nearly every cube configuration occurs).
// A seed gives the same phantom on every platform (see splitmix64.h).
#include <cstdint>
#include <vector>

#include "phantom.h"

namespace mvox::sim {

// One Gaussian blob: amplitude * 2^-(d / radius)^2 at distance d from the centre, so it falls
// to half its amplitude at `radius` (voxel units). It is cut to 0 beyond 5 radii (2^-25).
struct Blob {
  Point3 centre;
  double radius;
  double amplitude;
};

// A sum of `blob_count` Gaussian blobs with random centres (in the middle 80% of each axis),
// radii (uniform from 2 voxels to a tenth of the smallest dimension) and amplitudes in
// [0.6, 1.4). At a threshold of 0.5 each blob alone is a ball of at least half its radius;
// overlapping blobs merge into irregular components, chains of them close into handles.
// Radii up to a quarter of the grid were tried first: the largest blobs then swallow the rest
// into one component at any threshold that keeps the small ones.
class RandomBlobs final : public Phantom {
 public:
  // Throws std::invalid_argument for an empty grid.
  RandomBlobs(Grid grid, std::uint64_t seed, std::uint32_t blob_count);
  Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override;
  const char* name() const override { return "blobs"; }
  const std::vector<Blob>& blobs() const { return blobs_; }

 private:
  Grid grid_;
  std::vector<Blob> blobs_;
  std::vector<double> inv_radius_squared_;  // per blob
  // Blobs within the cutoff of slice z: slice_blobs_[slice_blob_begin_[z] .. [z + 1]).
  std::vector<std::uint32_t> slice_blob_begin_;
  std::vector<std::uint32_t> slice_blobs_;
};

// Each voxel is 1 with probability `inner_probability`, else 0, decided by a hash of
// (seed, x, y, z) alone: any slice, or any voxel, can be generated on its own, and a voxel's
// value does not depend on the grid size.
class RandomVoxels final : public Phantom {
 public:
  // Throws std::invalid_argument for an empty grid or a probability outside [0, 1].
  RandomVoxels(Grid grid, std::uint64_t seed, double inner_probability);
  Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override;
  const char* name() const override { return "random"; }

 private:
  Grid grid_;
  std::uint64_t seed_;
  double inner_probability_;
};

}  // namespace mvox::sim
