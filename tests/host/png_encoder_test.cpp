// The PNG encoder writes the bytes OpenCV's cv::imencode(".png") writes, so that every picture
// mvox wrote through OpenCV (goldens, --image, demo, phantom slices) is unchanged without it.
#include "write/png_encoder.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <vector>

namespace mvox {
namespace {

// An image with flat areas, ramps and noise, as pictures and slices have; rows `stride` samples
// apart (wider than the image, as a picture inside a larger buffer would be).
template <typename T>
std::vector<T> image(int width, int height, int stride, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<T> samples(static_cast<std::size_t>(stride) * height, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      samples[static_cast<std::size_t>(y) * stride + x] =
          static_cast<T>(y < height / 3       ? 0
                         : y < 2 * height / 3 ? x * 97
                                              : random());
  return samples;
}

template <typename T>
void expect_same_bytes_as_opencv(int width, int height) {
  const int stride = width + 3;
  std::vector<T> samples = image<T>(width, height, stride, width * 7 + height);
  SliceView slice;
  slice.samples = samples.data();
  slice.width = static_cast<std::uint32_t>(width);
  slice.height = static_cast<std::uint32_t>(height);
  slice.row_stride_bytes = stride * sizeof(T);
  slice.type = sizeof(T) == 1 ? SampleType::u8 : SampleType::u16;
  const cv::Mat mat(height, width, sizeof(T) == 1 ? CV_8UC1 : CV_16UC1, samples.data(),
                    slice.row_stride_bytes);
  std::vector<unsigned char> theirs;
  ASSERT_TRUE(cv::imencode(".png", mat, theirs));
  EXPECT_EQ(encode_png(slice), theirs) << width << "x" << height;
}

TEST(PngEncoder, EightBitPicturesAreOpenCvsBytes) {
  expect_same_bytes_as_opencv<std::uint8_t>(1, 1);
  expect_same_bytes_as_opencv<std::uint8_t>(512, 512);
  expect_same_bytes_as_opencv<std::uint8_t>(37, 211);
}

TEST(PngEncoder, SixteenBitSlicesAreOpenCvsBytes) {
  expect_same_bytes_as_opencv<std::uint16_t>(1, 1);
  expect_same_bytes_as_opencv<std::uint16_t>(64, 40);
  expect_same_bytes_as_opencv<std::uint16_t>(129, 3);
}

TEST(PngEncoder, RefusesSamplesPngCannotHold) {
  float samples[4] = {};
  SliceView slice;
  slice.samples = samples;
  slice.width = 2;
  slice.height = 2;
  slice.row_stride_bytes = 8;
  slice.type = SampleType::f32;
  EXPECT_ANY_THROW(encode_png(slice));
}

}  // namespace
}  // namespace mvox
