// FloatTexts must write exactly what std::to_chars writes for every float, whether the value is
// looked up for the first time, again, or after another value took its slot; and never more
// than kRoom bytes.
#include "write/mesh/float_texts.h"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace mvox {
namespace {

std::string library_text(float value) {
  char text[64];
  const std::to_chars_result result = std::to_chars(text, text + sizeof text, value);
  EXPECT_EQ(result.ec, std::errc());
  return std::string(text, result.ptr);
}

// put() into a buffer with guard bytes after the room it may use.
std::string cached_text(FloatTexts& texts, float value) {
  constexpr char kGuard = '\x5a';
  char buffer[FloatTexts::kRoom + 8];
  std::memset(buffer, kGuard, sizeof buffer);
  char* end = texts.put(buffer, value);
  for (std::size_t i = FloatTexts::kRoom; i < sizeof buffer; ++i)
    EXPECT_EQ(buffer[i], kGuard) << "put() wrote past its room at byte " << i;
  EXPECT_LE(static_cast<std::size_t>(end - buffer), FloatTexts::kLongestText);
  return std::string(buffer, end);
}

float from_bits(std::uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

TEST(FloatTexts, WritesTheLibrarysTextForSpecialValues) {
  FloatTexts texts;
  const float specials[] = {0.0f,
                            -0.0f,
                            1.0f,
                            -1.0f,
                            0.5f,
                            -0.5f,
                            100000.0f,  // "1e+05": the shorter of the two notations
                            1e6f,
                            123.5f,
                            std::numeric_limits<float>::min(),
                            -std::numeric_limits<float>::min(),
                            -1.00000075e-36f,  // the longest text: nine digits
                            std::numeric_limits<float>::max(),
                            -std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            -std::numeric_limits<float>::quiet_NaN()};
  for (int pass = 0; pass < 2; ++pass)  // the first time from scratch, then from the table
    for (float value : specials) EXPECT_EQ(cached_text(texts, value), library_text(value));
  EXPECT_EQ(library_text(-1.00000075e-36f), "-1.00000075e-36");
}

TEST(FloatTexts, WritesTheLibrarysTextForRandomBitsSeenOnceAndAgain) {
  FloatTexts texts;
  std::mt19937 random(20261127);
  std::vector<float> values;
  for (int i = 0; i < 200000; ++i) values.push_back(from_bits(random()));
  for (int pass = 0; pass < 2; ++pass)
    for (float value : values) ASSERT_EQ(cached_text(texts, value), library_text(value));
}

TEST(FloatTexts, WritesTheLibrarysTextForGridCoordinates) {
  // What a mesh on a grid writes: half voxels, times spacings, plus an origin; each many times.
  FloatTexts texts;
  const float spacings[] = {1.0f, 0.5f, 0.7f, 0.48828125f, 1.25f};
  for (float spacing : spacings)
    for (int repeat = 0; repeat < 3; ++repeat)
      for (int half = -1; half < 2100; ++half) {
        const float value = -12.5f + spacing * (0.5f * static_cast<float>(half));
        ASSERT_EQ(cached_text(texts, value), library_text(value)) << spacing << " " << half;
      }
}

TEST(FloatTexts, KeepsValuesApartThatShareASlot) {
  // Pairs of values that take the same slot, looked up in turn: each lookup must see that the
  // slot holds the other value's text.
  std::vector<std::pair<float, float>> pairs;
  std::vector<std::uint32_t> first_in_slot(std::size_t{1} << 16, 0);
  for (std::uint32_t bits = 0x3f800000u; pairs.size() < 2000; bits += 977) {
    std::uint32_t& first = first_in_slot[FloatTexts::slot_of(bits) % first_in_slot.size()];
    if (first != 0 && FloatTexts::slot_of(first) == FloatTexts::slot_of(bits))
      pairs.emplace_back(from_bits(first), from_bits(bits));
    first = bits;
  }
  FloatTexts texts;
  for (const auto& [a, b] : pairs)
    for (int turn = 0; turn < 3; ++turn) {
      ASSERT_EQ(cached_text(texts, a), library_text(a));
      ASSERT_EQ(cached_text(texts, b), library_text(b));
    }
}

TEST(FloatTexts, NoFloatNeedsMoreThanTheLongestText) {
  // A sweep of every 251st bit pattern (17 million floats) against kLongestText, so that a
  // library that wrote longer texts fails here rather than in a writer.
  std::size_t longest = 0;
  for (std::uint64_t bits = 0; bits <= 0xffffffffu; bits += 251) {
    char text[64];
    const std::to_chars_result result =
        std::to_chars(text, text + sizeof text, from_bits(static_cast<std::uint32_t>(bits)));
    longest = std::max(longest, static_cast<std::size_t>(result.ptr - text));
  }
  EXPECT_EQ(longest, FloatTexts::kLongestText);
}

}  // namespace
}  // namespace mvox
