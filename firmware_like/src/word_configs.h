#pragma once
// The configurations (cube.h: bit c set when corner c is inner) of the 64 cubes of one word of a
// cube row, from the eight words that hold each corner: bit cx of corners[c] is corner c of cube
// cx. PASS 3 (engine.cpp) asks for the configuration of each active cube of the word.
//
// With SSE2 or NEON (the x86-64 and A64 baselines, so no runtime check) all 64 are computed at
// once, as eight 8x8 bit-matrix transposes: interleaving the corner words' bytes gives, per group
// of 8 cubes, a 64-bit matrix whose byte c is corner c of those cubes; transposed, its byte i is
// cube i's configuration. That costs about as much as extracting eight bits for three cubes, and
// a word with any active cube has six (CThead) to nineteen (MRbrain) of them on average.
// Elsewhere each configuration is gathered bit by bit; all give identical results.
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__ARM_NEON) && defined(__AARCH64EL__)
#include <arm_neon.h>
#endif

namespace mvox {

#if defined(__SSE2__)

class WordConfigs {
 public:
  explicit WordConfigs(const std::uint64_t (&corners)[8]) {
    auto load = [&](int c) { return _mm_cvtsi64_si128(static_cast<long long>(corners[c])); };
    // Byte k of each pair of corners side by side, then of each four, then of all eight: lane g
    // of the four results holds the 8x8 matrix of cubes 8g..8g+7 (g = 2 * result + lane).
    const __m128i c01 = _mm_unpacklo_epi8(load(0), load(1));
    const __m128i c23 = _mm_unpacklo_epi8(load(2), load(3));
    const __m128i c45 = _mm_unpacklo_epi8(load(4), load(5));
    const __m128i c67 = _mm_unpacklo_epi8(load(6), load(7));
    const __m128i c0123_lo = _mm_unpacklo_epi16(c01, c23), c0123_hi = _mm_unpackhi_epi16(c01, c23);
    const __m128i c4567_lo = _mm_unpacklo_epi16(c45, c67), c4567_hi = _mm_unpackhi_epi16(c45, c67);
    auto* out = reinterpret_cast<__m128i*>(configs_);
    _mm_store_si128(out + 0, transpose8x8(_mm_unpacklo_epi32(c0123_lo, c4567_lo)));
    _mm_store_si128(out + 1, transpose8x8(_mm_unpackhi_epi32(c0123_lo, c4567_lo)));
    _mm_store_si128(out + 2, transpose8x8(_mm_unpacklo_epi32(c0123_hi, c4567_hi)));
    _mm_store_si128(out + 3, transpose8x8(_mm_unpackhi_epi32(c0123_hi, c4567_hi)));
  }

  unsigned operator[](int cx) const { return configs_[cx]; }

 private:
  // Transposes the 8x8 bit matrix in each 64-bit lane (byte = row, bit = column), by swapping
  // 2x2, then 4x4, then 8x8 blocks (Hacker's Delight, section 7-3).
  static __m128i transpose8x8(__m128i x) {
    x = swap_blocks<7>(x, _mm_set1_epi64x(0x00AA00AA00AA00AA));
    x = swap_blocks<14>(x, _mm_set1_epi64x(0x0000CCCC0000CCCC));
    return swap_blocks<28>(x, _mm_set1_epi64x(0x00000000F0F0F0F0));
  }
  template <int kShift>
  static __m128i swap_blocks(__m128i x, __m128i mask) {
    const __m128i t = _mm_and_si128(_mm_xor_si128(x, _mm_srli_epi64(x, kShift)), mask);
    return _mm_xor_si128(_mm_xor_si128(x, t), _mm_slli_epi64(t, kShift));
  }

  alignas(16) std::uint8_t configs_[64];
};

#elif defined(__ARM_NEON) && defined(__AARCH64EL__)

class WordConfigs {
 public:
  explicit WordConfigs(const std::uint64_t (&corners)[8]) {
    // The corner words as one 64-byte table (little-endian: byte 8c + g is byte g of corner c).
    // One table lookup gathers byte g of every corner for two groups of 8 cubes, g and g + 1: the
    // same matrices as SSE2's interleaving, in the same order.
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(corners);
    const uint8x16x4_t table = {
        {vld1q_u8(bytes), vld1q_u8(bytes + 16), vld1q_u8(bytes + 32), vld1q_u8(bytes + 48)}};
    const uint8x16_t groups01 = {0, 8, 16, 24, 32, 40, 48, 56, 1, 9, 17, 25, 33, 41, 49, 57};
    for (int pair = 0; pair < 4; ++pair) {
      const uint8x16_t matrices = vqtbl4q_u8(table, vaddq_u8(groups01, vdupq_n_u8(2 * pair)));
      vst1q_u8(configs_ + 16 * pair, transpose8x8(vreinterpretq_u64_u8(matrices)));
    }
  }

  unsigned operator[](int cx) const { return configs_[cx]; }

 private:
  // As SSE2's: the 8x8 bit matrix in each 64-bit lane, transposed by swapping 2x2, 4x4, 8x8 blocks.
  static uint8x16_t transpose8x8(uint64x2_t x) {
    x = swap_blocks<7>(x, vdupq_n_u64(0x00AA00AA00AA00AA));
    x = swap_blocks<14>(x, vdupq_n_u64(0x0000CCCC0000CCCC));
    return vreinterpretq_u8_u64(swap_blocks<28>(x, vdupq_n_u64(0x00000000F0F0F0F0)));
  }
  template <int kShift>
  static uint64x2_t swap_blocks(uint64x2_t x, uint64x2_t mask) {
    const uint64x2_t t = vandq_u64(veorq_u64(x, vshrq_n_u64(x, kShift)), mask);
    return veorq_u64(veorq_u64(x, t), vshlq_n_u64(t, kShift));
  }

  alignas(16) std::uint8_t configs_[64];
};

#else

class WordConfigs {
 public:
  explicit WordConfigs(const std::uint64_t (&corners)[8]) {
    for (int c = 0; c < 8; ++c) corners_[c] = corners[c];
  }

  unsigned operator[](int cx) const {
    unsigned config = 0;
    for (int c = 0; c < 8; ++c) config |= static_cast<unsigned>(corners_[c] >> cx & 1) << c;
    return config;
  }

 private:
  std::uint64_t corners_[8];
};

#endif

}  // namespace mvox
