#include "classify.h"

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__ARM_NEON) && defined(__AARCH64EL__)
#include <arm_neon.h>
#endif

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

// The definition of a chunk's mask: bit i is set when sample i of the n <= 64 at `samples` is
// inner. Written so that the compiler may vectorise it; the SSE2 and NEON versions below give the
// same bits for full chunks, faster.
template <typename Sample, typename Threshold>
std::uint64_t inner_mask_scalar(const unsigned char* samples, std::uint32_t n,
                                Threshold threshold) {
  std::uint64_t mask = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Threshold value =
        static_cast<Threshold>(load_sample<Sample>(samples + i * sizeof(Sample)));
    mask |= static_cast<std::uint64_t>(value >= threshold) << i;
  }
  return mask;
}

#if defined(__SSE2__)
// SSE2 is part of the x86-64 baseline, so these need no runtime check. Each compares 16 lanes at
// a time, gathers the lanes' sign bits with movemask and counts the inner lanes in `counts`.
// Only valid for thresholds inside the sample type's range (in_simd_range); the scalar loop
// handles the rest.

// Counts inner lanes without a popcount per word (x86-64 baseline has no POPCNT instruction):
// each byte of a compare result is 0 or -1 and is subtracted into 16 byte counters, which are
// summed (psadbw) before they can wrap: at most 4 per chunk of 64 samples.
class LaneCounts {
 public:
  static constexpr int kChunksBeforeWrap = 255 / 4;

  void add(__m128i inner_lanes) { bytes_ = _mm_sub_epi8(bytes_, inner_lanes); }

  std::uint64_t drain() {
    const __m128i sums = _mm_sad_epu8(bytes_, _mm_setzero_si128());
    bytes_ = _mm_setzero_si128();
    return static_cast<std::uint64_t>(_mm_cvtsi128_si32(sums)) +
           static_cast<std::uint64_t>(_mm_cvtsi128_si32(_mm_srli_si128(sums, 8)));
  }

 private:
  __m128i bytes_ = _mm_setzero_si128();
};

inline std::uint64_t lanes_to_bits(__m128i inner_lanes, int chunk, LaneCounts& counts) {
  counts.add(inner_lanes);
  return static_cast<std::uint64_t>(static_cast<std::uint16_t>(_mm_movemask_epi8(inner_lanes)))
         << (16 * chunk);
}

inline __m128i load16(const unsigned char* bytes) {
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes));
}

// u8: x >= t exactly when max(x, t) == x (SSE2 has no unsigned byte compare).
inline std::uint64_t inner_mask_u8(const unsigned char* samples, std::int32_t threshold,
                                   LaneCounts& counts) {
  const __m128i t = _mm_set1_epi8(static_cast<char>(threshold));
  std::uint64_t mask = 0;
  for (int c = 0; c < 4; ++c) {
    const __m128i x = load16(samples + 16 * c);
    mask |= lanes_to_bits(_mm_cmpeq_epi8(_mm_max_epu8(x, t), x), c, counts);
  }
  return mask;
}

// 16-bit: x >= t exactly when x > t - 1; unsigned samples are moved into the signed range by
// flipping their top bit. Two compares are packed (saturating, so -1 stays -1) into 16 bytes.
template <bool kUnsigned>
inline std::uint64_t inner_mask_16(const unsigned char* samples, std::int32_t threshold,
                                   LaneCounts& counts) {
  const int bias = kUnsigned ? 0x8000 : 0;
  const __m128i flip = _mm_set1_epi16(static_cast<short>(bias));
  const __m128i below = _mm_set1_epi16(static_cast<short>(threshold - 1 - bias));
  std::uint64_t mask = 0;
  for (int c = 0; c < 4; ++c) {
    const __m128i lo = _mm_xor_si128(load16(samples + 32 * c), flip);
    const __m128i hi = _mm_xor_si128(load16(samples + 32 * c + 16), flip);
    mask |= lanes_to_bits(_mm_packs_epi16(_mm_cmpgt_epi16(lo, below), _mm_cmpgt_epi16(hi, below)),
                          c, counts);
  }
  return mask;
}

// f32: an ordered compare, so NaN is never inner, as in the scalar loop. Four compares of four
// lanes are packed into 16 bytes.
inline std::uint64_t inner_mask_f32(const unsigned char* samples, float threshold,
                                    LaneCounts& counts) {
  const __m128 t = _mm_set1_ps(threshold);
  auto compare = [&](const unsigned char* at) {
    return _mm_castps_si128(_mm_cmpge_ps(_mm_loadu_ps(reinterpret_cast<const float*>(at)), t));
  };
  std::uint64_t mask = 0;
  for (int c = 0; c < 4; ++c) {
    const unsigned char* at = samples + 64 * c;
    const __m128i lo = _mm_packs_epi32(compare(at), compare(at + 16));
    const __m128i hi = _mm_packs_epi32(compare(at + 32), compare(at + 48));
    mask |= lanes_to_bits(_mm_packs_epi16(lo, hi), c, counts);
  }
  return mask;
}

template <typename Sample, typename Threshold>
std::uint64_t inner_mask_sse2(const unsigned char* samples, Threshold threshold,
                              LaneCounts& counts) {
  if constexpr (std::is_same_v<Sample, std::uint8_t>)
    return inner_mask_u8(samples, threshold, counts);
  if constexpr (std::is_same_v<Sample, std::uint16_t>)
    return inner_mask_16<true>(samples, threshold, counts);
  if constexpr (std::is_same_v<Sample, std::int16_t>)
    return inner_mask_16<false>(samples, threshold, counts);
  if constexpr (std::is_same_v<Sample, float>) return inner_mask_f32(samples, threshold, counts);
}

#elif defined(__ARM_NEON) && defined(__AARCH64EL__)
// NEON is part of every A64 CPU, so these need no runtime check either. Each compares 16 lanes at
// a time, and the inner voxels are counted from the mask (A64 has a popcount instruction). As for
// SSE2, only thresholds inside the sample type's range (in_simd_range). A64's float compares keep
// denormals (ARMv7's flush them to zero), so they agree with the scalar loop.

// NEON has no movemask: each lane keeps its own bit of a byte (1, 2, 4, ... 128, twice), and
// three rounds of pairwise adds gather the 64 lanes' bits, in order, into the low 8 bytes
// (little-endian only, hence __AARCH64EL__).
inline std::uint64_t lanes_to_bits(const uint8x16_t (&inner_lanes)[4]) {
  const uint8x16_t bit = {1, 2, 4, 8, 16, 32, 64, 128, 1, 2, 4, 8, 16, 32, 64, 128};
  const uint8x16_t l01 = vpaddq_u8(vandq_u8(inner_lanes[0], bit), vandq_u8(inner_lanes[1], bit));
  const uint8x16_t l23 = vpaddq_u8(vandq_u8(inner_lanes[2], bit), vandq_u8(inner_lanes[3], bit));
  const uint8x16_t l0123 = vpaddq_u8(l01, l23);
  return vgetq_lane_u64(vreinterpretq_u64_u8(vpaddq_u8(l0123, l0123)), 0);
}

// Loaded as bytes, so that no pointer to a wider sample is ever misaligned.
inline uint8x16_t load16(const unsigned char* bytes) { return vld1q_u8(bytes); }

inline std::uint64_t inner_mask_u8(const unsigned char* samples, std::int32_t threshold) {
  const uint8x16_t t = vdupq_n_u8(static_cast<std::uint8_t>(threshold));
  uint8x16_t lanes[4];
  for (int c = 0; c < 4; ++c) lanes[c] = vcgeq_u8(load16(samples + 16 * c), t);
  return lanes_to_bits(lanes);
}

// 16-bit: NEON compares unsigned and signed lanes alike, so no bias; each pair of compares is
// narrowed into 16 bytes.
template <bool kUnsigned>
inline std::uint64_t inner_mask_16(const unsigned char* samples, std::int32_t threshold) {
  auto compare = [&](const unsigned char* at) {
    if constexpr (kUnsigned)
      return vmovn_u16(vcgeq_u16(vreinterpretq_u16_u8(load16(at)),
                                 vdupq_n_u16(static_cast<std::uint16_t>(threshold))));
    else
      return vmovn_u16(vcgeq_s16(vreinterpretq_s16_u8(load16(at)),
                                 vdupq_n_s16(static_cast<std::int16_t>(threshold))));
  };
  uint8x16_t lanes[4];
  for (int c = 0; c < 4; ++c)
    lanes[c] = vcombine_u8(compare(samples + 32 * c), compare(samples + 32 * c + 16));
  return lanes_to_bits(lanes);
}

// f32: an ordered compare, so NaN is never inner, as in the scalar loop. Four compares of four
// lanes are narrowed into 16 bytes.
inline std::uint64_t inner_mask_f32(const unsigned char* samples, float threshold) {
  const float32x4_t t = vdupq_n_f32(threshold);
  auto compare = [&](const unsigned char* at) {
    return vmovn_u32(vcgeq_f32(vreinterpretq_f32_u8(load16(at)), t));
  };
  uint8x16_t lanes[4];
  for (int c = 0; c < 4; ++c) {
    const unsigned char* at = samples + 64 * c;
    lanes[c] = vcombine_u8(vmovn_u16(vcombine_u16(compare(at), compare(at + 16))),
                           vmovn_u16(vcombine_u16(compare(at + 32), compare(at + 48))));
  }
  return lanes_to_bits(lanes);
}

template <typename Sample, typename Threshold>
std::uint64_t inner_mask_neon(const unsigned char* samples, Threshold threshold) {
  if constexpr (std::is_same_v<Sample, std::uint8_t>) return inner_mask_u8(samples, threshold);
  if constexpr (std::is_same_v<Sample, std::uint16_t>)
    return inner_mask_16<true>(samples, threshold);
  if constexpr (std::is_same_v<Sample, std::int16_t>)
    return inner_mask_16<false>(samples, threshold);
  if constexpr (std::is_same_v<Sample, float>) return inner_mask_f32(samples, threshold);
}
#endif

// True when the vector compare is exact for this threshold: integer thresholds outside the sample
// type's range would wrap when narrowed to a lane (every sample is inner below the range, none
// above it), so those go through the scalar loop.
template <typename Sample, typename Threshold>
bool in_simd_range(Threshold threshold) {
  if constexpr (std::is_integral_v<Sample>)
    return threshold > std::numeric_limits<Sample>::min() &&
           threshold <= std::numeric_limits<Sample>::max();
  else
    return true;
}

// Builds each 64-voxel word as a whole and stores it shifted by one: voxel x lands on bit x + 1
// (bit_rows.h); bit 63 of a chunk carries into the next word. Returns the row's inner voxels.
template <typename Sample, typename Threshold>
std::uint64_t classify_row(const unsigned char* samples, std::uint32_t width, Threshold threshold,
                           bool simd, std::uint64_t* row, std::uint32_t row_words) {
  std::uint64_t inner = 0;
#if defined(__SSE2__)
  LaneCounts counts;
  int counted_chunks = 0;
#else
  (void)simd;
#endif
  std::uint64_t carry = 0;
  std::uint32_t w = 0;
  for (std::uint32_t x0 = 0; x0 < width; x0 += 64, ++w) {
    const std::uint32_t n = width - x0 < 64 ? width - x0 : 64;
    const unsigned char* chunk = samples + std::size_t{x0} * sizeof(Sample);
    std::uint64_t mask;
#if defined(__SSE2__)
    if (simd && n == 64) {
      mask = inner_mask_sse2<Sample>(chunk, threshold, counts);
      if (++counted_chunks == LaneCounts::kChunksBeforeWrap) {
        inner += counts.drain();
        counted_chunks = 0;
      }
    } else
#elif defined(__ARM_NEON) && defined(__AARCH64EL__)
    if (simd && n == 64) {
      mask = inner_mask_neon<Sample>(chunk, threshold);
      inner += static_cast<std::uint64_t>(set_bit_count(mask));  // A64 has a popcount: cnt
    } else
#endif
    {
      mask = inner_mask_scalar<Sample>(chunk, n, threshold);
      inner += static_cast<std::uint64_t>(set_bit_count(mask));
    }
    row[w] = mask << 1 | carry;
    carry = mask >> 63;
  }
  // The padding beyond the last voxel; a carry, when there is one, always has a word to go to.
  for (; w < row_words; ++w, carry = 0) row[w] = carry;
#if defined(__SSE2__)
  inner += counts.drain();
#endif
  return inner;
}

template <typename Sample, typename Threshold>
std::uint64_t classify_rows(const SliceView& slice, Threshold threshold, std::uint64_t* rows,
                            std::uint32_t row_words, std::uint8_t* occupied) {
  std::uint64_t inner = 0;
  const auto* bytes = static_cast<const unsigned char*>(slice.samples);
  const bool simd = in_simd_range<Sample>(threshold);
  for (std::uint32_t y = 0; y < slice.height; ++y) {
    const std::uint64_t row_inner =
        classify_row<Sample>(bytes + y * slice.row_stride_bytes, slice.width, threshold, simd,
                             rows + std::size_t{y} * row_words, row_words);
    occupied[y] = row_inner != 0;
    inner += row_inner;
  }
  return inner;
}

}  // namespace

std::uint64_t classify_slice(const SliceView& slice, const Thresholds& thresholds,
                             std::uint64_t* rows, std::uint32_t row_words, std::uint8_t* occupied) {
  switch (slice.type) {
    case SampleType::u8:
      return classify_rows<std::uint8_t>(slice, thresholds.integer, rows, row_words, occupied);
    case SampleType::u16:
      return classify_rows<std::uint16_t>(slice, thresholds.integer, rows, row_words, occupied);
    case SampleType::i16:
      return classify_rows<std::int16_t>(slice, thresholds.integer, rows, row_words, occupied);
    case SampleType::f32:
      return classify_rows<float>(slice, thresholds.real, rows, row_words, occupied);
  }
  return 0;
}

}  // namespace mvox
