// The slice image header reader (src/read/image_stack/image_header.h): what PNG, JPEG, BMP and PNM
// headers declare, checked against OpenCV's decoding of the same files, and the sizes refused
// before any decoder sees them.
#include "read/image_stack/image_header.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "deflate.h"
#include "read/compression_bounds.h"

namespace mvox {
namespace {

std::optional<ImageHeader> header_of(const std::string& bytes) {
  return parse_image_header(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
}

std::optional<ImageHeader> header_of(const std::vector<unsigned char>& bytes) {
  return parse_image_header(bytes.data(), bytes.size());
}

// Every format OpenCV writes that the reader knows: the header says what the decoder gives.
TEST(ImageHeader, AgreesWithOpenCvOnTheFilesOpenCvWrites) {
  cv::Mat grey8(11, 13, CV_8UC1), grey16(11, 13, CV_16UC1), colour(11, 13, CV_8UC3);
  cv::randu(grey8, 0, 255);
  cv::randu(grey16, 0, 65535);
  cv::randu(colour, 0, 255);
  struct Case {
    const char* extension;
    const cv::Mat* image;
  };
  for (const Case c :
       {Case{".png", &grey8}, Case{".png", &grey16}, Case{".png", &colour}, Case{".jpg", &grey8},
        Case{".jpg", &colour}, Case{".bmp", &grey8}, Case{".bmp", &colour}, Case{".pgm", &grey8},
        Case{".pgm", &grey16}, Case{".ppm", &colour}}) {
    SCOPED_TRACE(std::string(c.extension) + " depth " + std::to_string(c.image->depth()) +
                 " channels " + std::to_string(c.image->channels()));
    std::vector<unsigned char> file;
    ASSERT_TRUE(cv::imencode(c.extension, *c.image, file));
    const std::optional<ImageHeader> header = header_of(file);
    ASSERT_TRUE(header.has_value());
    const cv::Mat decoded = cv::imdecode(file, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    EXPECT_EQ(header->width, static_cast<std::uint32_t>(decoded.cols));
    EXPECT_EQ(header->height, static_cast<std::uint32_t>(decoded.rows));
    EXPECT_EQ(header->channels, decoded.channels());
    EXPECT_EQ(sample_bytes(header->type), decoded.elemSize1());
    EXPECT_EQ(decoded_image_bytes(*header), decoded.total() * decoded.elemSize());
    EXPECT_EQ(image_size_problem(*header), "");
  }
}

TEST(ImageHeader, JpegSegmentsBeforeTheFrameAndFillBytesAreWalked) {
  std::string jpeg = "\xFF\xD8";
  jpeg += std::string("\xFF\xE1\x00\x0A", 4) + "Exif" + std::string(4, '\0');  // APP1
  jpeg += std::string("\xFF\xFF\xFF\xDB\x00\x04\x00\x00", 8);  // fill bytes, a short DQT
  jpeg += std::string("\xFF\xC1\x00\x0B\x0C\x01\x2C\x00\xC8\x01\x01\x11\x00", 13);  // SOF1
  const auto header = header_of(jpeg);
  ASSERT_TRUE(header.has_value());
  EXPECT_EQ(header->width, 200u);
  EXPECT_EQ(header->height, 300u);
  EXPECT_EQ(header->type, SampleType::u16);  // 12-bit precision
  // A height of 0 (to come in a DNL marker) is not known from the header.
  jpeg[jpeg.size() - 8] = 0;
  jpeg[jpeg.size() - 7] = 0;
  EXPECT_FALSE(header_of(jpeg).has_value());
}

TEST(ImageHeader, PnmCommentsAndAsciiFormsAreRead) {
  const auto ascii = header_of(std::string("P2\n# made by hand\n  7 # width\n5\n1000\n1 2 3"));
  ASSERT_TRUE(ascii.has_value());
  EXPECT_EQ(ascii->width, 7u);
  EXPECT_EQ(ascii->height, 5u);
  EXPECT_EQ(ascii->type, SampleType::u16);
  const auto bitmap = header_of(std::string("P4 9 2 \xff\xff", 9));
  ASSERT_TRUE(bitmap.has_value());
  EXPECT_EQ(bitmap->type, SampleType::u8);
  EXPECT_FALSE(header_of(std::string("P5 7")).has_value());  // cut short
  EXPECT_FALSE(header_of(std::string("P5 0 5 255 ")).has_value());
}

TEST(ImageHeader, NotAnImageOrCutShortGivesNothing) {
  EXPECT_FALSE(header_of(std::string("hello, world")).has_value());
  EXPECT_FALSE(header_of(std::string("\x89PNG\r\n\x1a\n\x00\x00", 10)).has_value());
  EXPECT_FALSE(header_of(std::string("BM\x00\x00", 4)).has_value());
  EXPECT_FALSE(header_of(std::string()).has_value());
}

TEST(ImageHeader, SizesThatCannotBeDecodedAreNamed) {
  const std::vector<unsigned char> little =
      test::deflate_bytes(std::vector<unsigned char>(100), false);
  auto header = header_of(test::png_file(65535, 65535, 8, little));
  ASSERT_TRUE(header.has_value());
  EXPECT_NE(image_size_problem(*header).find("more than the 2^30 pixels"), std::string::npos);
  header = header_of(test::png_file(20000, 20000, 16, little));
  ASSERT_TRUE(header.has_value());
  EXPECT_EQ(header->stream_bytes, 20000u * (1 + 40000u));
  EXPECT_NE(image_size_problem(*header).find("cannot hold a 20000x20000 image"), std::string::npos)
      << image_size_problem(*header);
  // The largest image those bytes can hold passes.
  const std::uint64_t rows = (little.size() * kDeflateMaxRatio) / (1 + 1000);
  header = header_of(test::png_file(1000, static_cast<std::uint32_t>(rows), 8, little));
  EXPECT_EQ(image_size_problem(*header), "");
}

}  // namespace
}  // namespace mvox
