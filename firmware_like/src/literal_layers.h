#pragma once
// The literal engine's state: the merged segments of every cube in the two cube layers that a
// slice touches, and the paper's passes applied voxel by voxel as slices arrive.
//
// When slice s arrives, its inner voxels' octant triangles go to the cubes below it (layer
// s-1..s, `lower`) and above it (layer s..s+1, `upper`); the x and y passes merge the voxel pairs
// of slice s in both layers; the z pass merges the pairs between slices s-1 and s, which
// completes the lower layer. Nothing else is kept.
#include <cstdint>

#include "cube_merge.h"

namespace mvox {

class LiteralLayers {
 public:
  // Workspace bytes for slices of width x height (64-bit: the caller checks it fits).
  static std::uint64_t bytes(std::uint32_t width, std::uint32_t height) {
    return 2 * (std::uint64_t{width} + 1) * (std::uint64_t{height} + 1) * sizeof(CubeSurface);
  }

  // `storage` holds bytes(width, height) bytes; cleared here.
  void init(void* storage, std::uint32_t width, std::uint32_t height);

  // PHASES 1 and 2 for slice `rows` (bit rows, bit_rows.h) on top of slice `below_rows`
  // (the previous slice, or all outer for the first).
  void add_slice(const std::uint64_t* below_rows, const std::uint64_t* rows,
                 std::uint32_t row_words);

  // The completed lower layer's cube at column cx (0..width) and row cy (0..height).
  const CubeSurface& lower_cube(std::uint32_t cx, std::uint32_t cy) const {
    return lower_[std::size_t{cy} * (width_ + 1) + cx];
  }

  // Moves on one layer: the upper layer becomes the lower one; a new empty upper layer.
  void advance();

 private:
  static std::size_t cubes_per_layer(std::uint32_t width, std::uint32_t height) {
    return std::size_t{width + 1} * (height + 1);
  }
  CubeSurface& cube(CubeSurface* layer, std::uint32_t cx, std::uint32_t cy) {
    return layer[std::size_t{cy} * (width_ + 1) + cx];
  }

  CubeSurface* lower_ = nullptr;
  CubeSurface* upper_ = nullptr;
  std::uint32_t width_ = 0;
  std::uint32_t height_ = 0;
};

}  // namespace mvox
