#pragma once
// The vertices on one family of parallel voxel edges (x-edges of a slice, y-edges of a slice, or
// z-edges between two slices): their count and first global index, and for the literal engine a
// bit per edge plus, per 64-bit word, the number of set bits before it. A vertex's global index
// is then a rank query: base + prefix + popcount, so the literal engine never stores an index per
// voxel (about 0.19 bytes per edge instead of 4). The fast engine needs neither: it numbers
// vertices by running counts in PASS 3's walk (engine.cpp, for_each_surface_cube).
#include <cstdint>

#include "bit_rows.h"
#include "mvox/assert.h"

namespace mvox {

struct EdgePlane {
  std::uint64_t* bits = nullptr;    // rows * row_words words, same padding as bit_rows.h; or null
  std::uint32_t* prefix = nullptr;  // per word: set bits in all earlier words of the plane; or null
  std::uint32_t rows = 0;
  std::uint32_t row_words = 0;
  std::uint32_t base = 0;   // global index of the plane's first vertex
  std::uint32_t count = 0;  // vertices in the plane

  // Index of the vertex on edge (row, j); that edge must have a vertex.
  std::uint32_t index(std::uint32_t row, std::uint32_t j) const {
    const std::uint32_t w = row * row_words + (j >> 6);
    const std::uint64_t below = (std::uint64_t{1} << (j & 63)) - 1;
    MVOX_DEBUG_ASSERT(bits && row < rows && (bits[w] >> (j & 63) & 1));
    return base + prefix[w] + static_cast<std::uint32_t>(set_bit_count(bits[w] & below));
  }
};

}  // namespace mvox
