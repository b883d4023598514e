#include "literal_layers.h"

#include <new>

#include "bit_rows.h"

namespace mvox {

void LiteralLayers::init(void* storage, std::uint32_t width, std::uint32_t height) {
  width_ = width;
  height_ = height;
  const std::size_t cubes = cubes_per_layer(width, height);
  lower_ = static_cast<CubeSurface*>(storage);
  upper_ = lower_ + cubes;
  for (std::size_t i = 0; i < 2 * cubes; ++i) new (lower_ + i) CubeSurface();
}

void LiteralLayers::advance() {
  CubeSurface* emptied = lower_;
  lower_ = upper_;
  upper_ = emptied;
  const std::size_t cubes = cubes_per_layer(width_, height_);
  for (std::size_t i = 0; i < cubes; ++i) upper_[i].segment_count = 0;
}

// A cube holds the voxel at column x as its corner bx (0 = lower) when cx = x + 1 - bx; same for
// rows. The lower layer holds this slice as its upper corners (bz = 1), the upper layer as bz = 0.
void LiteralLayers::add_slice(const std::uint64_t* below_rows, const std::uint64_t* rows,
                              std::uint32_t row_words) {
  auto inner = [&](const std::uint64_t* slice, std::uint32_t x, std::uint32_t y) {
    return test_bit(slice + std::size_t{y} * row_words, x + 1);
  };
  CubeSurface* layer_for_bz[2] = {upper_, lower_};

  // PHASE 1: eight octant triangles per inner voxel, each into the cube its octant lies in.
  for (std::uint32_t y = 0; y < height_; ++y)
    for (std::uint32_t x = 0; x < width_; ++x) {
      if (!inner(rows, x, y)) continue;
      for (int corner = 0; corner < cube::kCorners; ++corner) {
        const int bx = cube::corner_bit(corner, 0), by = cube::corner_bit(corner, 1);
        const int bz = cube::corner_bit(corner, 2);
        add_octant_triangle(cube(layer_for_bz[bz], x + 1 - bx, y + 1 - by), corner);
      }
    }

  // PHASE 2, x pass: voxel pairs (x, x+1) of this slice; four cubes share each pair's vertex.
  for (std::uint32_t y = 0; y < height_; ++y)
    for (std::uint32_t x = 0; x + 1 < width_; ++x) {
      if (!inner(rows, x, y) || !inner(rows, x + 1, y)) continue;
      for (int bz = 0; bz < 2; ++bz)
        for (int by = 0; by < 2; ++by)
          merge_at_edge(cube(layer_for_bz[bz], x + 1, y + 1 - by), by + 2 * bz);
    }

  // y pass: voxel pairs (y, y+1).
  for (std::uint32_t y = 0; y + 1 < height_; ++y)
    for (std::uint32_t x = 0; x < width_; ++x) {
      if (!inner(rows, x, y) || !inner(rows, x, y + 1)) continue;
      for (int bz = 0; bz < 2; ++bz)
        for (int bx = 0; bx < 2; ++bx)
          merge_at_edge(cube(layer_for_bz[bz], x + 1 - bx, y + 1), 4 + bx + 2 * bz);
    }

  // z pass: voxel pairs between the slice below and this one, all in the lower layer.
  for (std::uint32_t y = 0; y < height_; ++y)
    for (std::uint32_t x = 0; x < width_; ++x) {
      if (!inner(below_rows, x, y) || !inner(rows, x, y)) continue;
      for (int by = 0; by < 2; ++by)
        for (int bx = 0; bx < 2; ++bx)
          merge_at_edge(cube(lower_, x + 1 - bx, y + 1 - by), 8 + bx + 2 * by);
    }
}

}  // namespace mvox
