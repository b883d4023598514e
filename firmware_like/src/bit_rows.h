#pragma once
// A slice as rows of bits, one bit per voxel: set = inner. Each row is padded with an outer
// voxel on both sides, so bit j stands for column x = j - 1, bits 0 and width + 1 are always 0,
// and so are all bits beyond. With the padding, boundary cubes and vertices need no special path.
#include <cstddef>
#include <cstdint>

namespace mvox {

constexpr std::uint32_t padded_row_words(std::uint32_t width) { return (width + 2 + 63) / 64; }

inline bool test_bit(const std::uint64_t* row, std::uint32_t j) {
  return row[j >> 6] >> (j & 63) & 1;
}

// Word w of the row shifted down by one bit: bit j of the result is bit j + 1 of the row.
inline std::uint64_t shifted_down(const std::uint64_t* row, std::uint32_t w, std::uint32_t words) {
  const std::uint64_t carry = w + 1 < words ? row[w + 1] << 63 : 0;
  return row[w] >> 1 | carry;
}

inline int lowest_set_bit(std::uint64_t word) { return __builtin_ctzll(word); }

inline int set_bit_count(std::uint64_t word) {
#if defined(__POPCNT__) || defined(__aarch64__)
  return __builtin_popcountll(word);
#else
  // Without the POPCNT instruction (x86-64 baseline) __builtin_popcountll is a libgcc call; the
  // branch-free count (Hacker's Delight, figure 5-2) inlines to a dozen instructions.
  word = word - ((word >> 1) & 0x5555555555555555u);
  word = (word & 0x3333333333333333u) + ((word >> 2) & 0x3333333333333333u);
  word = (word + (word >> 4)) & 0x0F0F0F0F0F0F0F0Fu;
  return static_cast<int>((word * 0x0101010101010101u) >> 56);
#endif
}

}  // namespace mvox
