// jpeg_slice_decoder.h: valid JPEG slices give exactly what OpenCV's cv::imdecode gives (its
// libjpeg is the same Debian library); damage that libjpeg only warns about is refused in one
// mvox::Error naming the file, with nothing on standard error; colour, lying headers and
// allocation failures are refused too.
#include "read/image_stack/jpeg_slice_decoder.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "error.h"
#include "error_capture.h"
#include "file_io.h"
#include "jpeg_damage.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using Bytes = std::vector<unsigned char>;

// A grayscale image with smooth parts, edges and noise, so every kind of block occurs.
cv::Mat test_image(int width, int height, int seed) {
  cv::Mat image(height, width, CV_8UC1);
  cv::RNG random(static_cast<std::uint64_t>(seed));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(
          (x * 255 / width + (y > height / 2 ? 60 : 0) + random.uniform(0, 40)) % 256);
  return image;
}

Bytes encode(const cv::Mat& image, const std::vector<int>& parameters = {}) {
  Bytes bytes;
  EXPECT_TRUE(cv::imencode(".jpg", image, bytes, parameters));
  return bytes;
}

struct Decoded {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  Bytes samples;
};

Decoded decode(const Bytes& jpeg, const std::string& path = "slice.jpg") {
  Decoded decoded;
  decode_jpeg_slice(path, jpeg.data(), jpeg.size(), [&](std::uint32_t width, std::uint32_t height) {
    decoded.width = width;
    decoded.height = height;
    decoded.samples.resize(std::size_t{width} * height);
    return decoded.samples.data();
  });
  return decoded;
}

// What OpenCV gives for the same bytes, with the flags ImageStackSource used for JPEG.
Decoded opencv_decode(const Bytes& jpeg) {
  const cv::Mat image = cv::imdecode(jpeg, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  EXPECT_EQ(image.type(), CV_8UC1);
  Decoded decoded{
      static_cast<std::uint32_t>(image.cols), static_cast<std::uint32_t>(image.rows), {}};
  for (int y = 0; y < image.rows; ++y)
    decoded.samples.insert(decoded.samples.end(), image.ptr(y), image.ptr(y) + image.cols);
  return decoded;
}

void expect_same_as_opencv(const Bytes& jpeg) {
  const Decoded ours = decode(jpeg);
  const Decoded theirs = opencv_decode(jpeg);
  EXPECT_EQ(ours.width, theirs.width);
  EXPECT_EQ(ours.height, theirs.height);
  EXPECT_TRUE(ours.samples == theirs.samples) << "samples differ from OpenCV's";
}

// Standard error goes to a scratch file while this exists; written() says how much arrived.
class StderrCapture {
 public:
  StderrCapture() : file_(std::tmpfile()), saved_(::dup(STDERR_FILENO)) {
    std::fflush(stderr);
    ::dup2(::fileno(file_), STDERR_FILENO);
  }
  ~StderrCapture() {
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
    std::fclose(file_);
  }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  long written() const {
    std::fflush(stderr);
    return ::lseek(::fileno(file_), 0, SEEK_END);
  }

 private:
  std::FILE* file_;
  int saved_;
};

// What decoding `jpeg` refused with, checking that nothing reached standard error meanwhile.
std::string refusal_of(const Bytes& jpeg) {
  StderrCapture capture;
  const std::string message = test::error_of([&] { decode(jpeg); });
  EXPECT_EQ(capture.written(), 0) << "libjpeg wrote on standard error";
  return message;
}

// True when OpenCV decodes `jpeg` into an image, as mvox took it before; its libjpeg's warning
// ("Corrupt JPEG data: ...") is kept off the test's output.
bool opencv_accepts(const Bytes& jpeg) {
  StderrCapture capture;
  return !cv::imdecode(jpeg, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR).empty();
}

TEST(JpegSliceDecoder, SamplesAreOpenCvsForEverySizeAndCodingOption) {
  const std::vector<std::vector<int>> options = {
      {},
      {cv::IMWRITE_JPEG_QUALITY, 100},
      {cv::IMWRITE_JPEG_QUALITY, 5},
      {cv::IMWRITE_JPEG_RST_INTERVAL, 1},
      {cv::IMWRITE_JPEG_RST_INTERVAL, 3},
      {cv::IMWRITE_JPEG_PROGRESSIVE, 1},
      {cv::IMWRITE_JPEG_PROGRESSIVE, 1, cv::IMWRITE_JPEG_RST_INTERVAL, 2},
      {cv::IMWRITE_JPEG_OPTIMIZE, 1},
  };
  // Sizes that are and are not multiples of the 8x8 blocks and 16x16 MCUs.
  const std::vector<std::pair<int, int>> sizes = {{1, 1},   {7, 5},   {8, 8},     {16, 16},
                                                  {17, 33}, {64, 48}, {250, 131}, {1023, 9}};
  int seed = 0;
  for (const auto& [width, height] : sizes) {
    for (const std::vector<int>& parameters : options) {
      SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + ", option set " +
                   std::to_string(&parameters - options.data()));
      const Bytes jpeg = encode(test_image(width, height, ++seed), parameters);
      expect_same_as_opencv(jpeg);
    }
  }
}

TEST(JpegSliceDecoder, RestartIntervalAndProgressiveFilesAreWhatTheySay) {
  // Guards the test above: the options really produce restart markers and progressive scans.
  const cv::Mat image = test_image(64, 48, 1);
  const Bytes restarts = encode(image, {cv::IMWRITE_JPEG_RST_INTERVAL, 1});
  const test::ScanData scan = test::first_scan_data(restarts);
  int markers = 0;
  for (std::size_t at = scan.begin; at + 1 < scan.end; ++at)
    markers += restarts[at] == 0xff && restarts[at + 1] >= 0xd0 && restarts[at + 1] <= 0xd7;
  EXPECT_GE(markers, 10);
  const Bytes progressive = encode(image, {cv::IMWRITE_JPEG_PROGRESSIVE, 1});
  const Bytes sof2 = {0xff, 0xc2};
  EXPECT_NE(std::search(progressive.begin(), progressive.end(), sof2.begin(), sof2.end()),
            progressive.end());
}

// Any JPEG in the shared datasets (none are there today): the same samples as OpenCV, or, for
// a colour one, the colour refusal.
TEST(JpegSliceDecoder, RealJpegFromTheSharedDatasets) {
  const fs::path root = MVOX_SHARED_DATASETS;
  std::error_code error;
  if (!fs::is_directory(root, error)) GTEST_SKIP() << root << " is absent";
  int tried = 0;
  for (auto entry = fs::recursive_directory_iterator(root, error);
       !error && entry != fs::recursive_directory_iterator() && tried < 5; entry.increment(error)) {
    if (!entry->is_regular_file(error) || entry->file_size(error) > (64u << 20)) continue;
    std::ifstream in(entry->path(), std::ios::binary);
    char start[3] = {};
    if (!in.read(start, 3) || !is_jpeg_file(reinterpret_cast<unsigned char*>(start), 3)) continue;
    in.seekg(0);
    const Bytes jpeg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    SCOPED_TRACE(entry->path().string());
    ++tried;
    if (cv::imdecode(jpeg, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR).channels() == 1)
      expect_same_as_opencv(jpeg);
    else
      EXPECT_CONTAINS(refusal_of(jpeg), "colour image (");
  }
  if (tried == 0) GTEST_SKIP() << "no JPEG file under " << root;
}

TEST(JpegSliceDecoder, ScanCutShortAndClosedWithEndOfImageIsRefusedWherever) {
  const Bytes jpeg = encode(test_image(40, 24, 2), {cv::IMWRITE_JPEG_RST_INTERVAL, 2});
  const test::ScanData scan = test::first_scan_data(jpeg);
  ASSERT_GT(scan.end - scan.begin, 100u);
  // OpenCV takes such a file as good (with a warning on standard error): what mvox did.
  EXPECT_TRUE(opencv_accepts(test::cut_in_scan(jpeg, (scan.end - scan.begin) / 2)));
  for (std::size_t kept = 0; kept < scan.end - scan.begin; ++kept) {
    SCOPED_TRACE("cut after " + std::to_string(kept) + " bytes of the scan");
    const std::string message = refusal_of(test::cut_in_scan(jpeg, kept));
    EXPECT_EQ(message.rfind("slice.jpg: cannot decode JPEG: Corrupt JPEG data: ", 0), 0u)
        << message;
  }
  // Without restart markers too.
  const Bytes plain = encode(test_image(40, 24, 3));
  const test::ScanData plain_scan = test::first_scan_data(plain);
  EXPECT_CONTAINS(
      refusal_of(test::cut_in_scan(plain, (plain_scan.end - plain_scan.begin) / 3)),
      "slice.jpg: cannot decode JPEG: Corrupt JPEG data: premature end of data segment");
}

TEST(JpegSliceDecoder, JunkRestartMarkersAreRefused) {
  const Bytes jpeg = encode(test_image(64, 48, 4), {cv::IMWRITE_JPEG_RST_INTERVAL, 1});
  EXPECT_TRUE(opencv_accepts(test::renumber_restart_marker(jpeg)));
  EXPECT_CONTAINS(refusal_of(test::renumber_restart_marker(jpeg)),
                  "slice.jpg: cannot decode JPEG: Corrupt JPEG data: found marker 0x");
  const test::ScanData scan = test::first_scan_data(jpeg);
  for (std::size_t at = 0; at < scan.end - scan.begin; at += 7) {
    SCOPED_TRACE("junk at byte " + std::to_string(at) + " of the scan");
    EXPECT_CONTAINS(refusal_of(test::insert_restart_markers(jpeg, at)),
                    "slice.jpg: cannot decode JPEG: Corrupt JPEG data: ");
  }
  // In a scan without a restart interval.
  EXPECT_CONTAINS(refusal_of(test::insert_restart_markers(encode(test_image(64, 48, 5)), 50)),
                  "slice.jpg: cannot decode JPEG: Corrupt JPEG data: ");
}

TEST(JpegSliceDecoder, ColourIsRefusedAsColour) {
  cv::Mat colour(10, 12, CV_8UC3, cv::Scalar(10, 200, 30));
  EXPECT_EQ(refusal_of(encode(colour)),
            "slice.jpg: colour image (3 channels): convert to grayscale first");
}

TEST(JpegSliceDecoder, NotAJpegIsRefusedByLibjpegInOneLine) {
  const Bytes garbage = {0xff, 0xd8, 0xff, 0xe0, 0x00, 0x02, 0x12, 0x34, 0xff, 0xd9};
  const std::string message = refusal_of(garbage);
  EXPECT_EQ(message.rfind("slice.jpg: cannot decode JPEG: ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

// Rewrites the size in the first SOF segment.
Bytes with_declared_size(Bytes jpeg, std::uint16_t width, std::uint16_t height) {
  for (std::size_t at = 2; at + 9 < jpeg.size();) {
    const unsigned char code = jpeg[at + 1];
    if (code == 0xc0 || code == 0xc1 || code == 0xc2) {
      jpeg[at + 5] = static_cast<unsigned char>(height >> 8);
      jpeg[at + 6] = static_cast<unsigned char>(height);
      jpeg[at + 7] = static_cast<unsigned char>(width >> 8);
      jpeg[at + 8] = static_cast<unsigned char>(width);
      return jpeg;
    }
    at += 2 + (std::size_t{jpeg[at + 2]} << 8 | jpeg[at + 3]);
  }
  ADD_FAILURE() << "no SOF segment";
  return jpeg;
}

TEST(JpegSliceDecoder, SequentialFileDeclaringMoreThanItCanCodeIsRefusedBeforeAllocating) {
  const Bytes lying = with_declared_size(encode(test_image(16, 16, 6)), 65000, 65000);
  bool allocated = false;
  const std::string message = test::error_of([&] {
    decode_jpeg_slice("big.jpg", lying.data(), lying.size(), [&](std::uint32_t, std::uint32_t) {
      allocated = true;
      return static_cast<unsigned char*>(nullptr);
    });
  });
  EXPECT_FALSE(allocated);
  EXPECT_EQ(message, "big.jpg: JPEG declares 65000x65000 samples, more than its " +
                         std::to_string(lying.size()) +
                         " bytes of sequential Huffman data can code");
}

TEST(JpegSliceDecoder, AllocationFailureNamesTheBytes) {
  const Bytes jpeg = encode(test_image(30, 20, 7));
  const std::string message = test::error_of([&] {
    decode_jpeg_slice(
        "slice.jpg", jpeg.data(), jpeg.size(),
        [&](std::uint32_t, std::uint32_t) -> unsigned char* { throw std::bad_alloc(); });
  });
  EXPECT_EQ(message, "slice.jpg: out of memory: cannot allocate 600 bytes for the 30x20 slice");
}

// The fuzzer's seeds (fuzz/corpus/jpeg_slice_decoder_fuzzer/), small files of every kind the
// decoder meets, intact and damaged. MVOX_WRITE_FUZZ_SEEDS=DIR writes them into DIR; the test
// checks what each committed seed must give.
struct Seed {
  std::string name;
  Bytes bytes;
  bool valid;  // decodes to what OpenCV gives; otherwise refused
};

std::vector<Seed> fuzz_seeds() {
  const Bytes restarts = encode(test_image(17, 33, 11), {cv::IMWRITE_JPEG_RST_INTERVAL, 1});
  const test::ScanData scan = test::first_scan_data(restarts);
  return {
      {"baseline_8x8.jpg", encode(test_image(8, 8, 10)), true},
      {"restarts_17x33.jpg", restarts, true},
      {"progressive_40x24.jpg", encode(test_image(40, 24, 12), {cv::IMWRITE_JPEG_PROGRESSIVE, 1}),
       true},
      {"optimized_q5_23x9.jpg",
       encode(test_image(23, 9, 13), {cv::IMWRITE_JPEG_OPTIMIZE, 1, cv::IMWRITE_JPEG_QUALITY, 5}),
       true},
      {"cut_in_scan.jpg", test::cut_in_scan(restarts, (scan.end - scan.begin) / 2), false},
      {"renumbered_restart.jpg", test::renumber_restart_marker(restarts), false},
      {"colour_4x4.jpg", encode(cv::Mat(4, 4, CV_8UC3, cv::Scalar(10, 200, 30))), false},
  };
}

TEST(JpegSliceDecoder, FuzzSeeds) {
  for (const Seed& seed : fuzz_seeds()) {
    SCOPED_TRACE(seed.name);
    const Bytes bytes = test::committed_fuzz_seed(
        fs::path(MVOX_FUZZ_CORPUS) / "jpeg_slice_decoder_fuzzer", seed.name, seed.bytes);
    ASSERT_FALSE(bytes.empty());
    if (seed.valid)
      expect_same_as_opencv(bytes);
    else
      EXPECT_EQ(refusal_of(bytes).rfind("slice.jpg: ", 0), 0u);
  }
}

}  // namespace
}  // namespace mvox
