#pragma once
// The engine's PASS 1 (engine.cpp): one slice of samples to one slice of bit rows (bit_rows.h),
// inner = sample >= D.
#include <cstdint>

#include "mvox/slice.h"

namespace mvox {

// The threshold D turned into a comparison that is exact for each sample type:
// integers are inner when sample >= ceil(D); floats when sample >= the smallest float that is
// not below D (so a float sample compares exactly as it would in double). NaN is never inner.
struct Thresholds {
  std::int32_t integer = 0;
  float real = 0;
};

Thresholds make_thresholds(double threshold);

// Classifies `height` rows of `slice` into `rows` (row_words words per row, see
// padded_row_words) and sets occupied[y] to whether row y has an inner voxel, so that the later
// passes can skip empty rows without reading them. Returns the number of inner voxels.
std::uint64_t classify_slice(const SliceView& slice, const Thresholds& thresholds,
                             std::uint64_t* rows, std::uint32_t row_words, std::uint8_t* occupied);

}  // namespace mvox
