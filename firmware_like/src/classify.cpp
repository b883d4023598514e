#include "classify.h"

#include <cfloat>
#include <cmath>
#include <cstring>

#include "bit_rows.h"

namespace mvox {

Thresholds make_thresholds(double threshold) {
  Thresholds t;
  // Integer samples lie in [-32768, 65535]; clamping keeps ceil() in range and changes nothing.
  const double clamped = threshold < -70000.0  ? -70000.0
                         : threshold > 70000.0 ? 70000.0
                                               : threshold;
  t.integer = static_cast<std::int32_t>(std::ceil(clamped));
  // The smallest float not below D. Converting a double beyond the float range is undefined, so
  // those thresholds are mapped by hand: above FLT_MAX only +inf qualifies; below -FLT_MAX,
  // -FLT_MAX does (or -inf itself).
  if (threshold > FLT_MAX) {
    t.real = INFINITY;
  } else if (threshold < -FLT_MAX) {
    t.real = threshold == -INFINITY ? -INFINITY : -FLT_MAX;
  } else {
    t.real = static_cast<float>(threshold);
    if (static_cast<double>(t.real) < threshold) t.real = std::nextafter(t.real, INFINITY);
  }
  return t;
}

namespace {

// A sample at `bytes`, which need not be aligned. memcpy is the defined way to read a sample out
// of a byte buffer; compilers turn it into a plain load.
template <typename Sample>
Sample load_sample(const unsigned char* bytes) {
  Sample sample;
  std::memcpy(&sample, bytes, sizeof sample);
  return sample;
}

// Builds each 64-voxel word with shifts and ORs so the compiler can vectorise the comparison;
// voxel x lands on bit x + 1 (bit_rows.h).
template <typename Sample, typename Threshold>
std::uint64_t classify_row(const unsigned char* samples, std::uint32_t width, Threshold threshold,
                           std::uint64_t* row, std::uint32_t row_words) {
  std::memset(row, 0, row_words * sizeof(std::uint64_t));
  std::uint64_t inner = 0;
  for (std::uint32_t x0 = 0; x0 < width; x0 += 64) {
    const std::uint32_t n = width - x0 < 64 ? width - x0 : 64;
    const unsigned char* chunk = samples + std::size_t{x0} * sizeof(Sample);
    std::uint64_t mask = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const Threshold value =
          static_cast<Threshold>(load_sample<Sample>(chunk + i * sizeof(Sample)));
      mask |= static_cast<std::uint64_t>(value >= threshold) << i;
    }
    inner += static_cast<std::uint64_t>(set_bit_count(mask));
    const std::uint32_t w = x0 >> 6;
    row[w] |= mask << 1;
    if (w + 1 < row_words) row[w + 1] |= mask >> 63;
  }
  return inner;
}

template <typename Sample, typename Threshold>
std::uint64_t classify_rows(const SliceView& slice, Threshold threshold, std::uint64_t* rows,
                            std::uint32_t row_words) {
  std::uint64_t inner = 0;
  const auto* bytes = static_cast<const unsigned char*>(slice.samples);
  for (std::uint32_t y = 0; y < slice.height; ++y)
    inner += classify_row<Sample>(bytes + y * slice.row_stride_bytes, slice.width, threshold,
                                  rows + std::size_t{y} * row_words, row_words);
  return inner;
}

}  // namespace

std::uint64_t classify_slice(const SliceView& slice, const Thresholds& thresholds,
                             std::uint64_t* rows, std::uint32_t row_words) {
  switch (slice.type) {
    case SampleType::u8:
      return classify_rows<std::uint8_t>(slice, thresholds.integer, rows, row_words);
    case SampleType::u16:
      return classify_rows<std::uint16_t>(slice, thresholds.integer, rows, row_words);
    case SampleType::i16:
      return classify_rows<std::int16_t>(slice, thresholds.integer, rows, row_words);
    case SampleType::f32: return classify_rows<float>(slice, thresholds.real, rows, row_words);
  }
  return 0;
}

}  // namespace mvox
