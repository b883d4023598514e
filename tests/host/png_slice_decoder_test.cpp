// The PNG slice decoder against OpenCV: the very samples cv::imdecode gives, for every grey PNG
// layout (1-, 2-, 4-, 8- and 16-bit, interlaced or not, odd sizes), so that a PNG stack decoded
// without OpenCV gives the surface it gave with it; and what it leaves to OpenCV.
#include "read/image_stack/png_slice_decoder.h"

#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <vector>

#include "error.h"
#include "support/error_capture.h"
#include "support/libpng_writer.h"

namespace mvox {
namespace {

// A PNG written with libpng: grey samples `values` (one per pixel, below 2^bit_depth), or with
// `color_type` and a tRNS chunk when asked, so every layout a scanner might export is covered.
std::vector<unsigned char> make_png(int width, int height, int bit_depth, bool interlaced,
                                    const std::vector<unsigned>& values,
                                    int color_type = PNG_COLOR_TYPE_GRAY,
                                    bool transparent = false) {
  const int channels = color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2 : 1;
  const int bits_per_pixel = bit_depth * channels;
  const std::size_t row_bytes = (static_cast<std::size_t>(width) * bits_per_pixel + 7) / 8;
  std::vector<std::vector<unsigned char>> rows(height, std::vector<unsigned char>(row_bytes));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        const unsigned v = c == 0 ? values[static_cast<std::size_t>(y) * width + x] : 255;
        const std::size_t sample = static_cast<std::size_t>(x) * channels + c;
        if (bit_depth == 16) {
          rows[y][2 * sample] = static_cast<unsigned char>(v >> 8);  // big-endian in the file
          rows[y][2 * sample + 1] = static_cast<unsigned char>(v);
        } else if (bit_depth == 8) {
          rows[y][sample] = static_cast<unsigned char>(v);
        } else {
          const std::size_t bit = sample * bit_depth;
          rows[y][bit / 8] |= static_cast<unsigned char>(v << (8 - bit_depth - bit % 8));
        }
      }
    }
  }
  std::vector<png_bytep> pointers;
  for (auto& row : rows) pointers.push_back(row.data());
  return test::png_written_by_libpng([&](png_structp png, png_infop info) {
    png_set_IHDR(png, info, width, height, bit_depth, color_type,
                 interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (transparent) {
      png_color_16 value{};
      value.gray = 1;
      png_set_tRNS(png, info, nullptr, 0, &value);
    }
    png_write_info(png, info);
    png_write_image(png, pointers.data());
  });
}

std::vector<unsigned> random_values(int count, int bit_depth, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<unsigned> values(count);
  for (unsigned& v : values) v = random() & ((1u << bit_depth) - 1);
  return values;
}

// The decoder's samples and type.
struct Decoded {
  std::uint32_t width = 0, height = 0;
  SampleType type = SampleType::f32;
  std::vector<unsigned char> samples;
};

Decoded decode(const std::vector<unsigned char>& png) {
  Decoded decoded;
  decode_png_slice("s.png", png.data(), png.size(),
                   [&](std::uint32_t width, std::uint32_t height, SampleType type) {
                     decoded.width = width;
                     decoded.height = height;
                     decoded.type = type;
                     decoded.samples.resize(std::size_t{width} * height * sample_bytes(type));
                     return decoded.samples.data();
                   });
  return decoded;
}

struct Layout {
  int bit_depth;
  bool interlaced;
};

class PngLayouts : public ::testing::TestWithParam<Layout> {};

TEST_P(PngLayouts, GiveOpenCvsSamples) {
  const Layout layout = GetParam();
  for (const auto& [width, height] : {std::pair{1, 1}, std::pair{7, 5}, std::pair{33, 17}}) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height));
    const std::vector<unsigned char> png =
        make_png(width, height, layout.bit_depth, layout.interlaced,
                 random_values(width * height, layout.bit_depth, width * 31 + height));
    ASSERT_TRUE(is_plain_grey_png(png.data(), png.size()));
    const Decoded mine = decode(png);
    const cv::Mat theirs = cv::imdecode(
        cv::Mat(1, static_cast<int>(png.size()), CV_8UC1, const_cast<unsigned char*>(png.data())),
        cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    ASSERT_FALSE(theirs.empty());
    ASSERT_EQ(theirs.channels(), 1);
    EXPECT_EQ(mine.width, static_cast<std::uint32_t>(theirs.cols));
    EXPECT_EQ(mine.height, static_cast<std::uint32_t>(theirs.rows));
    EXPECT_EQ(mine.type, theirs.depth() == CV_16U ? SampleType::u16 : SampleType::u8);
    ASSERT_EQ(theirs.depth(), layout.bit_depth == 16 ? CV_16U : CV_8U);
    const std::size_t row_bytes = static_cast<std::size_t>(width) * theirs.elemSize();
    for (int y = 0; y < height; ++y)
      EXPECT_EQ(std::memcmp(mine.samples.data() + y * row_bytes, theirs.ptr(y), row_bytes), 0)
          << "row " << y;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryGreyLayout, PngLayouts,
                         ::testing::Values(Layout{1, false}, Layout{2, false}, Layout{4, false},
                                           Layout{8, false}, Layout{16, false}, Layout{1, true},
                                           Layout{8, true}, Layout{16, true}),
                         [](const ::testing::TestParamInfo<Layout>& info) {
                           return std::to_string(info.param.bit_depth) + "bit" +
                                  (info.param.interlaced ? "Interlaced" : "");
                         });

TEST(PngSliceDecoder, LeavesColourAlphaAndTransparencyToOpenCv) {
  const std::vector<unsigned> values(12, 1);
  const auto alpha = make_png(4, 3, 8, false, values, PNG_COLOR_TYPE_GRAY_ALPHA);
  EXPECT_FALSE(is_plain_grey_png(alpha.data(), alpha.size()));
  const auto transparent = make_png(4, 3, 8, false, values, PNG_COLOR_TYPE_GRAY, true);
  EXPECT_FALSE(is_plain_grey_png(transparent.data(), transparent.size()));
  const auto plain = make_png(4, 3, 8, false, values);
  EXPECT_TRUE(is_plain_grey_png(plain.data(), plain.size()));
  const unsigned char not_png[40] = "GIF89a";
  EXPECT_FALSE(is_plain_grey_png(not_png, sizeof not_png));
}

TEST(PngSliceDecoder, DamagedImageDataIsAnErrorNamingTheFile) {
  std::vector<unsigned char> png = make_png(33, 17, 8, false, random_values(33 * 17, 8, 5));
  // The IDAT chunk's data start after signature (8), IHDR (25) and the chunk's own header (8).
  // Damaging the zlib stream and fixing nothing else is what libpng must catch itself (its CRC
  // check would catch it first otherwise, so it is switched off by rewriting the CRC).
  const std::size_t idat = 8 + 25;
  ASSERT_EQ(std::memcmp(png.data() + idat + 4, "IDAT", 4), 0);
  const std::uint32_t length = std::uint32_t{png[idat]} << 24 | std::uint32_t{png[idat + 1]} << 16 |
                               std::uint32_t{png[idat + 2]} << 8 | png[idat + 3];
  png[idat + 8] ^= 0xFF;  // the zlib header
  const std::uint32_t crc =
      static_cast<std::uint32_t>(crc32(crc32(0, nullptr, 0), png.data() + idat + 4, length + 4));
  for (int i = 0; i < 4; ++i)
    png[idat + 8 + length + i] = static_cast<unsigned char>(crc >> (24 - 8 * i));
  EXPECT_CONTAINS(test::error_of([&] { decode(png); }), "s.png: cannot decode PNG: ");
}

}  // namespace
}  // namespace mvox
