// image_file_check.h: PNG and JPEG files are refused when truncated or corrupt, before libpng
// or libjpeg print on standard error or decode a wrong slice; intact files pass.
#include "read/image_stack/image_file_check.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

namespace mvox {
namespace {

std::vector<unsigned char> encoded(const std::string& extension, int type, int width, int height) {
  cv::Mat image(height, width, type);
  // Noise compresses badly, so the pixel data spans several chunks or segments.
  cv::randu(image, 0, type == CV_16UC1 ? 65535 : 255);
  std::vector<unsigned char> bytes;
  EXPECT_TRUE(cv::imencode(extension, image, bytes)) << extension;
  return bytes;
}

std::string problem_of(const std::vector<unsigned char>& bytes, std::size_t size) {
  return image_file_problem(bytes.data(), size);
}

TEST(ImageFileCheck, IntactFilesPassWhateverTheirSize) {
  // The CRC is computed by libpng when OpenCV writes: agreeing on every chunk size checks ours.
  for (const int side : {1, 3, 17, 64, 300}) {
    for (const int type : {CV_8UC1, CV_16UC1}) {
      const auto png = encoded(".png", type, side, side + 2);
      EXPECT_EQ(problem_of(png, png.size()), "") << side;
    }
    const auto jpeg = encoded(".jpg", CV_8UC1, side, side + 2);
    EXPECT_EQ(problem_of(jpeg, jpeg.size()), "") << side;
  }
}

TEST(ImageFileCheck, EveryTruncationOfAPngIsRefused) {
  const auto png = encoded(".png", CV_16UC1, 40, 30);
  // Up to 7 bytes there is no signature: nothing to check, the decoder refuses such a file.
  for (std::size_t size = 8; size < png.size(); ++size)
    ASSERT_EQ(problem_of(png, size).rfind(
                  "truncated PNG: the file ends at byte " + std::to_string(size), 0),
              0u)
        << size << ": " << problem_of(png, size);
}

TEST(ImageFileCheck, EverySingleByteCorruptionOfAPngIsRefused) {
  auto png = encoded(".png", CV_8UC1, 24, 20);
  for (std::size_t at = 8; at < png.size(); ++at) {
    png[at] ^= 0x10;
    const std::string problem = problem_of(png, png.size());
    EXPECT_FALSE(problem.empty()) << "byte " << at;
    png[at] ^= 0x10;
  }
  EXPECT_EQ(problem_of(png, png.size()), "");
}

TEST(ImageFileCheck, PngProblemsSayWhatIsWrong) {
  auto png = encoded(".png", CV_8UC1, 24, 20);
  png[8 + 8] ^= 1;  // the first byte of IHDR's data
  EXPECT_EQ(problem_of(png, png.size()),
            "corrupt PNG: the IHDR chunk at byte 8 fails its CRC check");
  png[8 + 8] ^= 1;
  png[8 + 7] = 'X';  // IHDR renamed
  EXPECT_EQ(problem_of(png, png.size()), "corrupt PNG: the first chunk is not a 13-byte IHDR");
  png[8 + 7] = 'R';
  png[8] = 0x80;  // a length beyond PNG's 2^31 - 1
  EXPECT_NE(problem_of(png, png.size()).find("claims"), std::string::npos);
  png[8] = 0;
  // libpng ignores what follows IEND, and so do we.
  png.insert(png.end(), {'t', 'r', 'a', 'i', 'l'});
  EXPECT_EQ(problem_of(png, png.size()), "");
}

TEST(ImageFileCheck, TruncatedJpegIsRefusedTrailingZerosAreNot) {
  auto jpeg = encoded(".jpg", CV_8UC1, 32, 32);
  for (std::size_t size = 3; size < jpeg.size(); ++size)
    ASSERT_EQ(problem_of(jpeg, size).rfind("truncated JPEG", 0), 0u) << size;
  jpeg.insert(jpeg.end(), 16, 0);
  EXPECT_EQ(problem_of(jpeg, jpeg.size()), "");
}

TEST(ImageFileCheck, OtherFormatsAreLeftToTheirDecoders) {
  for (const char* extension : {".bmp", ".pgm", ".tif"}) {
    const auto bytes = encoded(extension, CV_8UC1, 16, 16);
    EXPECT_EQ(problem_of(bytes, bytes.size() / 2), "") << extension;
  }
  EXPECT_EQ(image_file_problem(nullptr, 0), "");
}

}  // namespace
}  // namespace mvox
