// PASS 1 (classify.h) against its definition, sample by sample: a voxel is inner when its sample,
// compared in double, is >= D. The rows are wide enough for the vectorised 64-sample chunks (SSE2
// on x86-64, NEON on aarch64: whichever the build has) and end in a partial chunk, the samples
// start misaligned, and the thresholds sit at and beyond each type's range, where the vector
// compares would wrap.
#include "classify.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bit_rows.h"

namespace mvox {
namespace {

template <typename Sample>
void expect_exact_classification(SampleType type, const std::vector<Sample>& values,
                                 const std::vector<double>& thresholds) {
  std::mt19937 random(7);
  // 4100: more 64-sample chunks in a row than the vector path counts before it must sum.
  for (std::uint32_t width : {1u, 63u, 64u, 65u, 130u, 200u, 4100u}) {
    const std::uint32_t height = 3;
    const std::size_t stride = width * sizeof(Sample) + 3;  // rows start misaligned
    std::vector<unsigned char> bytes(1 + stride * height);
    std::vector<Sample> samples(std::size_t{width} * height);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      samples[i] = values[random() % values.size()];
      std::memcpy(&bytes[1 + (i / width) * stride + (i % width) * sizeof(Sample)], &samples[i],
                  sizeof(Sample));
    }
    const SliceView slice{bytes.data() + 1, width, height, stride, type};
    const std::uint32_t words = padded_row_words(width);
    for (double threshold : thresholds) {
      std::vector<std::uint64_t> rows(std::size_t{words} * height, ~std::uint64_t{0});
      std::vector<std::uint8_t> occupied(height, 2);
      const std::uint64_t inner =
          classify_slice(slice, make_thresholds(threshold), rows.data(), words, occupied.data());
      std::uint64_t expected_inner = 0;
      for (std::uint32_t y = 0; y < height; ++y) {
        const std::uint64_t inner_before_row = expected_inner;
        for (std::uint32_t j = 0; j < words * 64; ++j) {
          const bool in_slice = j >= 1 && j <= width;
          const bool expected =
              in_slice && static_cast<double>(samples[y * width + (j - 1)]) >= threshold;
          expected_inner += expected;
          ASSERT_EQ(test_bit(&rows[std::size_t{y} * words], j), expected)
              << "width " << width << " threshold " << threshold << " row " << y << " bit " << j;
        }
        EXPECT_EQ(occupied[y], expected_inner > inner_before_row ? 1 : 0)
            << "width " << width << " threshold " << threshold << " row " << y;
      }
      EXPECT_EQ(inner, expected_inner) << "width " << width << " threshold " << threshold;
    }
  }
}

// One inner sample at each position of two full chunks sets its own bit and no other: the vector
// paths gather their lanes' results into bits in several steps, each of which could reorder them.
template <typename Sample>
void expect_each_sample_alone(SampleType type, Sample outer, Sample inner, double threshold) {
  const std::uint32_t width = 128;
  const std::uint32_t words = padded_row_words(width);
  for (std::uint32_t x = 0; x < width; ++x) {
    std::vector<Sample> samples(width, outer);
    samples[x] = inner;
    const SliceView slice{samples.data(), width, 1, width * sizeof(Sample), type};
    std::vector<std::uint64_t> row(words);
    std::uint8_t occupied = 0;
    ASSERT_EQ(classify_slice(slice, make_thresholds(threshold), row.data(), words, &occupied), 1u)
        << "sample " << x;
    for (std::uint32_t j = 0; j < words * 64; ++j)
      ASSERT_EQ(test_bit(row.data(), j), j == x + 1) << "sample " << x << " bit " << j;
  }
}

TEST(Classify, EachSampleAloneSetsItsOwnBit) {
  expect_each_sample_alone<std::uint8_t>(SampleType::u8, 99, 100, 100);
  expect_each_sample_alone<std::uint16_t>(SampleType::u16, 599, 600, 600);
  expect_each_sample_alone<std::int16_t>(SampleType::i16, -1025, -1024, -1024);
  expect_each_sample_alone<float>(SampleType::f32, 0.0f, 0.5f, 0.5);
}

TEST(Classify, UnsignedBytes) {
  expect_exact_classification<std::uint8_t>(
      SampleType::u8, {0, 1, 99, 100, 101, 127, 128, 129, 254, 255},
      {-5, 0, 0.5, 1, 100, 127.5, 128, 129, 255, 255.5, 256, 300});
}

TEST(Classify, UnsignedShorts) {
  expect_exact_classification<std::uint16_t>(
      SampleType::u16, {0, 1, 599, 600, 601, 32767, 32768, 32769, 65534, 65535},
      {-1, 0, 1, 600, 32767, 32768, 32768.5, 65535, 65536, 1e9});
}

TEST(Classify, SignedShorts) {
  expect_exact_classification<std::int16_t>(
      SampleType::i16, {-32768, -32767, -1025, -1024, -1, 0, 1, 32766, 32767},
      {-40000, -32768, -32767, -1024, -0.5, 0, 1, 32767, 32768});
}

TEST(Classify, Floats) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  expect_exact_classification<float>(
      SampleType::f32,
      {-INFINITY, -FLT_MAX, -1.0f, 0.0f, 0.1f, std::nextafter(0.1f, 0.0f), 1e30f, FLT_MAX, INFINITY,
       nan},
      {-INFINITY, -1e300, -1, 0, 0.1, static_cast<double>(0.1f), 1e30, 1e300, INFINITY});
}

}  // namespace
}  // namespace mvox
