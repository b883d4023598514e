// Image stacks (src/read/image_stack/image_stack_source.h): slices written by OpenCV read back in
// natural order, 8 and 16 bits exactly, and every slice that does not fit refused naming its
// file: another size or bit depth, colour, an unsupported depth, corrupt, truncated or missing.
#include "read/image_stack/image_stack_source.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "file_io.h"
#include "read/input_format.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::error_of;
using test::read_all;
using test::read_through;
using test::ScratchDirectory;
using test::touch;
using test::write_bytes;

// 8-bit value of pixel (x, y) of slice `index` (1-based, as in the file name).
std::uint8_t slice_pixel(int index, int x, int y) {
  return static_cast<std::uint8_t>(index * 16 + x + 2 * y);
}

TEST(ImageStack, ReadsSlicesInNaturalOrder) {
  ScratchDirectory dir;
  constexpr int kWidth = 7;  // odd and unequal sizes catch swapped axes
  constexpr int kHeight = 5;
  constexpr int kCount = 12;
  for (int index : {7, 12, 1, 10, 3, 11, 2, 9, 5, 4, 8, 6}) {  // scrambled write order
    cv::Mat image(kHeight, kWidth, CV_8U);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) image.at<std::uint8_t>(y, x) = slice_pixel(index, x, y);
    }
    ASSERT_TRUE(cv::imwrite(dir / ("slice" + std::to_string(index) + ".png"), image));
  }
  touch(dir / "notes.txt");  // not an image: the directory listing skips it

  std::unique_ptr<SliceSource> source = open_slice_source({dir.str()}, std::nullopt);
  ASSERT_NE(dynamic_cast<ImageStackSource*>(source.get()), nullptr);
  EXPECT_EQ(source->info().width, static_cast<std::uint32_t>(kWidth));
  EXPECT_EQ(source->info().height, static_cast<std::uint32_t>(kHeight));
  EXPECT_EQ(source->info().depth, static_cast<std::uint32_t>(kCount));
  EXPECT_EQ(source->info().type, SampleType::u8);
  EXPECT_EQ(source->info().spacing[2], 1.0);

  const auto slices = read_all<std::uint8_t>(*source);
  ASSERT_EQ(slices.size(), static_cast<std::size_t>(kCount));
  for (int k = 0; k < kCount; ++k) {
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        ASSERT_EQ(slices[k][y * kWidth + x], slice_pixel(k + 1, x, y))
            << "slice " << k << " x " << x << " y " << y;
      }
    }
  }
}

// Writes two 16-bit slices with values beyond 8 and 15 bits and reads them back exactly.
template <typename T>
void expect_16_bit_round_trip(const std::string& extension, int cv_type, SampleType type,
                              const std::vector<T>& values) {
  ScratchDirectory dir;
  constexpr int kWidth = 5;
  constexpr int kHeight = 3;
  ASSERT_EQ(values.size(), static_cast<std::size_t>(kWidth * kHeight));
  std::vector<std::vector<T>> written;
  for (int index = 1; index <= 2; ++index) {
    cv::Mat image(kHeight, kWidth, cv_type);
    std::vector<T> slice = values;
    if (index == 2) std::reverse(slice.begin(), slice.end());
    for (int i = 0; i < kWidth * kHeight; ++i) image.at<T>(i / kWidth, i % kWidth) = slice[i];
    ASSERT_TRUE(cv::imwrite(dir / ("s" + std::to_string(index) + extension), image));
    written.push_back(slice);
  }
  std::unique_ptr<SliceSource> source = open_slice_source({dir.str()}, std::nullopt);
  EXPECT_EQ(source->info().type, type);
  EXPECT_EQ(read_all<T>(*source), written);
}

TEST(ImageStack, Png16BitRoundTripsExactly) {
  expect_16_bit_round_trip<std::uint16_t>(
      ".png", CV_16U, SampleType::u16,
      {0, 1, 255, 256, 1000, 3272, 32767, 32768, 40000, 50001, 65534, 65535, 12345, 300, 7});
}

TEST(ImageStack, Tiff16BitRoundTripsExactly) {
  expect_16_bit_round_trip<std::uint16_t>(
      ".tif", CV_16U, SampleType::u16,
      {0, 1, 255, 256, 1000, 3272, 32767, 32768, 40000, 50001, 65534, 65535, 12345, 300, 7});
}

TEST(ImageStack, TiffSigned16BitKeepsNegativeValues) {
  expect_16_bit_round_trip<std::int16_t>(
      ".tiff", CV_16S, SampleType::i16,
      {-32768, -1024, -1, 0, 1, 255, 256, 32767, -300, 1000, -2, 3, 4, 5, 6});
}

TEST(ImageStack, Png8BitRoundTripsExactly) {
  ScratchDirectory dir;
  cv::Mat image(4, 64, CV_8U);
  for (int i = 0; i < 256; ++i) image.at<std::uint8_t>(i / 64, i % 64) = static_cast<uint8_t>(i);
  ASSERT_TRUE(cv::imwrite(dir / "only.png", image));
  std::unique_ptr<SliceSource> source = open_slice_source({dir / "only.png"}, std::nullopt);
  const auto slices = read_all<std::uint8_t>(*source);
  ASSERT_EQ(slices.size(), 1u);
  for (int i = 0; i < 256; ++i) ASSERT_EQ(slices[0][i], i);
}

TEST(ImageStack, RefusesSliceOfAnotherSize) {
  ScratchDirectory dir;
  ASSERT_TRUE(cv::imwrite(dir / "slice1.png", cv::Mat(5, 7, CV_8U, cv::Scalar(1))));
  ASSERT_TRUE(cv::imwrite(dir / "slice2.png", cv::Mat(5, 7, CV_8U, cv::Scalar(2))));
  ASSERT_TRUE(cv::imwrite(dir / "slice10.png", cv::Mat(7, 5, CV_8U, cv::Scalar(3))));
  const std::string message = error_of([&] { read_through({dir.str()}, std::nullopt); });
  EXPECT_CONTAINS(message, dir / "slice10.png: image is 5x7, expected 7x5");
}

// Slices are listed as files and opened later, each at its turn. One removed meanwhile is named
// as missing; one replaced by a FIFO kept the run waiting in open() for a writer that never
// came, and is refused instead.
TEST(ImageStack, ASliceRemovedOrReplacedByAFifoAfterListingIsRefusedNamingIt) {
  for (const bool fifo : {false, true}) {
    ScratchDirectory dir;
    for (int i = 1; i <= 3; ++i)
      ASSERT_TRUE(cv::imwrite(dir / ("s" + std::to_string(i) + ".png"),
                              cv::Mat(5, 7, CV_8U, cv::Scalar(i))));
    std::unique_ptr<SliceSource> source = open_slice_source({dir.str()}, std::nullopt);
    fs::remove(dir / "s2.png");
    if (fifo) ASSERT_EQ(::mkfifo((dir / "s2.png").c_str(), 0600), 0);
    const std::string message = error_of([&] { read_all<std::uint8_t>(*source); });
    EXPECT_CONTAINS(message,
                    dir / (fifo ? "s2.png: is no longer a regular file" : "s2.png: no such file"));
  }
}

TEST(ImageStack, RefusesSliceOfAnotherBitDepth) {
  ScratchDirectory dir;
  ASSERT_TRUE(cv::imwrite(dir / "slice1.png", cv::Mat(5, 7, CV_16U, cv::Scalar(1000))));
  ASSERT_TRUE(cv::imwrite(dir / "slice2.png", cv::Mat(5, 7, CV_8U, cv::Scalar(2))));
  const std::string message = error_of([&] { read_through({dir.str()}, std::nullopt); });
  EXPECT_CONTAINS(message, dir / "slice2.png: image is 8-bit");
  EXPECT_CONTAINS(message, "16-bit");
}

TEST(ImageStack, RefusesColourImages) {
  ScratchDirectory dir;
  fs::create_directories(dir / "first");
  fs::create_directories(dir / "later");
  ASSERT_TRUE(cv::imwrite(dir / "first/s1.png", cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3))));
  ASSERT_TRUE(cv::imwrite(dir / "first/s2.png", cv::Mat(4, 4, CV_8U, cv::Scalar(1))));
  ASSERT_TRUE(cv::imwrite(dir / "later/s1.png", cv::Mat(4, 4, CV_8U, cv::Scalar(1))));
  ASSERT_TRUE(cv::imwrite(dir / "later/s2.bmp", cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3))));

  // The first slice is decoded when the source opens, so info() is exact: refused right there.
  const std::string first = error_of([&] { open_slice_source({dir / "first"}, std::nullopt); });
  EXPECT_CONTAINS(first, dir / "first/s1.png: colour image");
  EXPECT_CONTAINS(first, "convert to grayscale first");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "later"}, std::nullopt); }),
                  dir / "later/s2.bmp: colour image");
}

TEST(ImageStack, RefusesUnsupportedBitDepth) {
  ScratchDirectory dir;
  ASSERT_TRUE(cv::imwrite(dir / "float.tif", cv::Mat(4, 4, CV_32F, cv::Scalar(1.5))));
  // Directly: through open_slice_source a TIFF-only input goes to TiffStackSource, which reads
  // float pages (tiff_stack_source_test.cpp).
  const std::string message = error_of([&] { ImageStackSource source({dir / "float.tif"}); });
  EXPECT_CONTAINS(message, dir / "float.tif: image is 32-bit float");
}

TEST(ImageStack, RefusesCorruptAndTruncatedImages) {
  ScratchDirectory dir;
  // Noise compresses badly, so half the file cuts deep into the pixel data.
  cv::Mat noise(64, 64, CV_16U);
  cv::randu(noise, 0, 65535);
  fs::create_directories(dir / "truncated");
  ASSERT_TRUE(cv::imwrite(dir / "truncated/s1.png", noise));
  ASSERT_TRUE(cv::imwrite(dir / "truncated/s2.png", noise));
  fs::resize_file(dir / "truncated/s2.png", fs::file_size(dir / "truncated/s2.png") / 2);
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "truncated"}, std::nullopt); }),
                  dir / "truncated/s2.png: truncated PNG: the file ends at byte");

  // libjpeg would decode a truncated JPEG into a grey bottom with only a warning.
  fs::create_directories(dir / "truncated_jpeg");
  cv::Mat noise8(64, 64, CV_8U);
  cv::randu(noise8, 0, 255);
  ASSERT_TRUE(cv::imwrite(dir / "truncated_jpeg/s1.jpg", noise8));
  ASSERT_TRUE(cv::imwrite(dir / "truncated_jpeg/s2.jpg", noise8));
  fs::resize_file(dir / "truncated_jpeg/s2.jpg", fs::file_size(dir / "truncated_jpeg/s2.jpg") - 2);
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "truncated_jpeg"}, std::nullopt); }),
                  dir / "truncated_jpeg/s2.jpg: truncated JPEG");
  // OpenCV's own readers say why, in the one message.
  fs::create_directories(dir / "truncated_pgm");
  ASSERT_TRUE(cv::imwrite(dir / "truncated_pgm/s1.pgm", noise8));
  ASSERT_TRUE(cv::imwrite(dir / "truncated_pgm/s2.pgm", noise8));
  fs::resize_file(dir / "truncated_pgm/s2.pgm", fs::file_size(dir / "truncated_pgm/s2.pgm") / 2);
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "truncated_pgm"}, std::nullopt); }),
      dir / "truncated_pgm/s2.pgm: cannot decode image: Unexpected end of input stream");

  const std::string text = "this is not an image";
  write_bytes(dir / "garbage/s1.png", std::vector<unsigned char>(text.begin(), text.end()));
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "garbage"}, std::nullopt); }),
                  dir / "garbage/s1.png: cannot read image");

  touch(dir / "empty_file/s1.tif");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "empty_file"}, std::nullopt); }),
                  dir / "empty_file/s1.tif");
}

TEST(ImageStack, RefusesMissingInputs) {
  ScratchDirectory dir;
  fs::create_directories(dir / "empty");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "empty"}, std::nullopt); }), dir / "empty");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "missing.png"}, std::nullopt); }),
                  dir / "missing.png");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "slice*.png"}, std::nullopt); }),
                  dir / "slice*.png");
  // A constructor given a file that vanished after listing names it too.
  EXPECT_CONTAINS(error_of([&] { ImageStackSource source({dir / "gone.png"}); }), dir / "gone.png");
}

}  // namespace
}  // namespace mvox
