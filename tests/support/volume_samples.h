#pragma once
// Test support for the volume file readers: phantom samples of each sample type, their bytes in
// either byte order, and every sample a source delivers, so that a test can write a file with
// known contents and compare what comes back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "mvox/slice_source.h"
#include "phantom.h"
#include "phantom_factory.h"
#include "read/raw/raw_format.h"

namespace mvox::test {

// A partial-volume density in [0, 1] mapped onto most of T's range, so that every byte of a
// sample matters (a byte-order or sign mistake changes values).
template <typename T>
T sample_from_density(double density) {
  if constexpr (std::is_same_v<T, float>) {
    return static_cast<float>(density * 3.5 - 1.25);
  } else if constexpr (std::is_same_v<T, std::int8_t>) {
    return static_cast<T>(std::lround(density * 250.0 - 125.0));
  } else if constexpr (std::is_same_v<T, std::uint8_t>) {
    return static_cast<T>(std::lround(density * 250.0));
  } else if constexpr (std::is_same_v<T, std::int16_t>) {
    return static_cast<T>(std::lround(density * 60000.0 - 30000.0));
  } else {
    return static_cast<T>(std::lround(density * 65000.0));
  }
}

// The 3-D Shepp-Logan head with partial-volume edges on a width x height x depth grid, x
// fastest, as samples of type T.
template <typename T>
std::vector<T> phantom_samples(std::uint32_t width, std::uint32_t height, std::uint32_t depth) {
  const auto phantom = sim::make_phantom("shepp-logan", {width, height, depth}, 1);
  std::vector<T> samples;
  samples.reserve(std::size_t{width} * height * depth);
  for (std::uint32_t z = 0; z < depth; ++z)
    for (std::uint32_t y = 0; y < height; ++y)
      for (std::uint32_t x = 0; x < width; ++x)
        samples.push_back(sample_from_density<T>(phantom->partial_volume_density(x, y, z)));
  return samples;
}

// The samples' bytes in `order`, whatever the host's order.
template <typename T>
std::vector<unsigned char> encode_samples(const std::vector<T>& samples, ByteOrder order) {
  static_assert(sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4);
  // The sample's bits as an unsigned number, so that shifts pick bytes by significance.
  using Bits = std::conditional_t<sizeof(T) == 1, std::uint8_t,
                                  std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint32_t>>;
  std::vector<unsigned char> bytes(samples.size() * sizeof(T));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    Bits bits;
    std::memcpy(&bits, &samples[i], sizeof(T));
    for (std::size_t b = 0; b < sizeof(T); ++b) {
      const std::size_t at = order == ByteOrder::little ? b : sizeof(T) - 1 - b;
      bytes[i * sizeof(T) + at] = static_cast<unsigned char>(bits >> (8 * b));
    }
  }
  return bytes;
}

// Every sample `source` delivers, x fastest, as T; checks each view against info() and T.
template <typename T>
std::vector<T> read_samples(SliceSource& source) {
  const VolumeInfo& info = source.info();
  EXPECT_EQ(sample_bytes(info.type), sizeof(T));
  std::vector<T> samples;
  SliceView view;
  std::uint32_t slices = 0;
  while (source.next_slice(&view)) {
    ++slices;
    EXPECT_EQ(view.width, info.width);
    EXPECT_EQ(view.height, info.height);
    EXPECT_EQ(view.type, info.type);
    for (std::uint32_t y = 0; y < view.height; ++y) {
      const char* row = static_cast<const char*>(view.samples) + y * view.row_stride_bytes;
      for (std::uint32_t x = 0; x < view.width; ++x) {
        T value;
        std::memcpy(&value, row + x * sizeof(T), sizeof(T));
        samples.push_back(value);
      }
    }
  }
  EXPECT_EQ(slices, info.depth);
  EXPECT_FALSE(source.next_slice(&view)) << "a finished source must stay finished";
  return samples;
}

}  // namespace mvox::test
