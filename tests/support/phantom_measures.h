#pragma once
// Test support for the phantoms (sim/): a phantom whose every voxel differs, and measures of the
// voxels at or above a threshold (count, 6-connected components, Euler characteristic) that the
// phantoms' tests compare with analytic values.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "phantom.h"

namespace mvox::test {

// density = x + 10 y + 100 z: every voxel different, so any axis swap or flip shows.
class AxisPhantom final : public sim::Phantom {
 public:
  explicit AxisPhantom(sim::Grid grid) : grid_(grid) {}
  sim::Grid grid() const override { return grid_; }
  float density(std::uint32_t x, std::uint32_t y, std::uint32_t z) const override {
    return static_cast<float>(x + 10.0 * y + 100.0 * z);
  }
  const char* name() const override { return "axis"; }

 private:
  sim::Grid grid_;
};

// The index of voxel (x, y, z) in a volume sampled by sim::sample_volume (x fastest).
std::size_t index_of(const sim::Grid& g, std::uint32_t x, std::uint32_t y, std::uint32_t z);

// Number of voxels with density >= threshold.
std::size_t count_at_least(const std::vector<float>& volume, float threshold);

// Number of 6-connected components of voxels with density >= threshold.
int count_components(const sim::Grid& g, const std::vector<float>& volume, float threshold);

// Euler characteristic of the voxels with density >= threshold, 6-connected: the cubical
// complex with a vertex per voxel, an edge per 6-adjacent pair, a square per 2x2 block and a
// cube per 2x2x2 block, which has the same topology as the 6-connected voxel set.
long euler_characteristic(const sim::Grid& g, const std::vector<float>& volume, float threshold);

}  // namespace mvox::test
