#pragma once
// Test support for the TIFF stack reader's tests: a page size that leaves edge tiles partly
// outside the image, striped and tiled layouts, multi-page files written with libtiff, and every
// sample the factory reads back from them.
#include <gtest/gtest.h>
#include <tiffio.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "mvox/slice_source.h"
#include "read/input_format.h"
#include "volume_samples.h"

namespace mvox::test::tiff_stack_files {

// Not multiples of the 16-pixel tiles, so that edge tiles are partly outside the image.
constexpr std::uint32_t kWidth = 37, kHeight = 29, kDepth = 7;

struct Layout {
  const char* name;
  bool tiled;
  std::uint32_t rows_per_strip;  // striped pages
  std::uint16_t compression;
};

inline constexpr Layout kLayouts[] = {
    {"striped, 4 rows per strip", false, 4, COMPRESSION_NONE},
    {"striped, one row per strip, deflate", false, 1, COMPRESSION_ADOBE_DEFLATE},
    {"tiled 16x16", true, 0, COMPRESSION_NONE},
    {"tiled 16x16, LZW", true, 0, COMPRESSION_LZW},
};

template <typename T>
std::uint16_t sample_format() {
  if constexpr (std::is_floating_point_v<T>) return SAMPLEFORMAT_IEEEFP;
  if constexpr (std::is_signed_v<T>) return SAMPLEFORMAT_INT;
  return SAMPLEFORMAT_UINT;
}

// Writes one page of `samples_per_pixel` x `bits` samples (pixels interleaved) and ends its
// directory; `extra` may set more tags first.
void write_page(TIFF* tiff, const void* pixels, std::uint32_t width, std::uint32_t height,
                std::uint16_t bits, std::uint16_t format, std::uint16_t samples_per_pixel,
                const Layout& layout, const std::function<void(TIFF*)>& extra = {});

// Writes `depth` pages of `samples` (x fastest, then y, then page).
template <typename T>
void write_stack(const std::string& path, const std::vector<T>& samples, std::uint32_t width,
                 std::uint32_t height, std::uint32_t first_page, std::uint32_t page_count,
                 const Layout& layout, const std::function<void(TIFF*)>& extra = {},
                 const char* mode = "w") {
  TIFF* tiff = TIFFOpen(path.c_str(), mode);
  ASSERT_NE(tiff, nullptr) << path;
  const std::size_t page_samples = std::size_t{width} * height;
  for (std::uint32_t page = first_page; page < first_page + page_count; ++page) {
    write_page(tiff, samples.data() + page * page_samples, width, height, 8 * sizeof(T),
               sample_format<T>(), 1, layout, extra);
  }
  TIFFClose(tiff);
}

// Every sample of the volume the factory opens for `inputs`.
template <typename T>
std::vector<T> read_stack(const std::vector<std::string>& inputs, VolumeInfo* info = nullptr) {
  auto source = open_slice_source(inputs, std::nullopt);
  if (info) *info = source->info();
  return test::read_samples<T>(*source);
}

// `size` bytes of `value`: strip and tile contents for tiff_bytes.h.
std::vector<unsigned char> filled(std::size_t size, unsigned char value);

}  // namespace mvox::test::tiff_stack_files
