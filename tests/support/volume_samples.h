#pragma once
// Test support for the slice and volume file readers: phantom samples of each sample type, their
// bytes in either byte order, and every sample a source delivers (all at once or slice by slice),
// so that a test can write a file with known contents and compare what comes back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "mvox/slice_source.h"
#include "phantom.h"
#include "phantom_factory.h"
#include "read/input_format.h"
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
        samples.push_back(sample_from_density<T>(phantom->partial_volume_density(x, y, z, 0.0)));
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

// encode_samples of each raw sample type, for braced lists of values and as function pointers.
inline std::vector<unsigned char> encode_u16(const std::vector<std::uint16_t>& values,
                                             ByteOrder order) {
  return encode_samples(values, order);
}
inline std::vector<unsigned char> encode_i16(const std::vector<std::int16_t>& values,
                                             ByteOrder order) {
  return encode_samples(values, order);
}
inline std::vector<unsigned char> encode_f32(const std::vector<float>& values, ByteOrder order) {
  return encode_samples(values, order);
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

// Reads every slice of `source` as samples of type T, checking the view against info() and
// that the view always points into the same memory, reused: one slice buffer, or the
// working_bytes() the source says it holds (RawVolumeSource reads several small slices at once).
template <typename T>
std::vector<std::vector<T>> read_all(SliceSource& source) {
  const VolumeInfo& info = source.info();
  std::vector<std::vector<T>> slices;
  const char* first_buffer = nullptr;
  SliceView view;
  while (source.next_slice(&view)) {
    EXPECT_EQ(view.width, info.width);
    EXPECT_EQ(view.height, info.height);
    EXPECT_EQ(view.type, info.type);
    EXPECT_EQ(sample_bytes(view.type), sizeof(T));
    EXPECT_GE(view.row_stride_bytes, view.width * sizeof(T));
    const auto* start = static_cast<const char*>(view.samples);
    if (first_buffer == nullptr) first_buffer = start;
    const std::size_t slice_bytes = view.row_stride_bytes * view.height;
    if (source.working_bytes() == 0) {
      EXPECT_EQ(start, first_buffer) << "slice " << slices.size() << " moved buffers";
    } else {
      EXPECT_LE(first_buffer, start) << "slice " << slices.size() << " left the buffer";
      EXPECT_LE(start + slice_bytes, first_buffer + source.working_bytes())
          << "slice " << slices.size() << " left the buffer";
    }
    std::vector<T> samples(static_cast<std::size_t>(view.width) * view.height);
    for (std::uint32_t y = 0; y < view.height; ++y) {
      std::memcpy(&samples[static_cast<std::size_t>(y) * view.width],
                  static_cast<const char*>(view.samples) + y * view.row_stride_bytes,
                  view.width * sizeof(T));
    }
    slices.push_back(std::move(samples));
  }
  EXPECT_FALSE(source.next_slice(&view)) << "a finished source must stay finished";
  EXPECT_EQ(slices.size(), info.depth);
  return slices;
}

// Opens the source and reads it to the end, so a refusal at any slice surfaces.
inline void read_through(const std::vector<std::string>& inputs,
                         const std::optional<RawFormat>& raw) {
  std::unique_ptr<SliceSource> source = open_slice_source(inputs, raw);
  SliceView view;
  while (source->next_slice(&view)) {
  }
}

}  // namespace mvox::test
