// Bad JPEG and TIFF data through the command line (the contract: support/bad_input.h): JPEG
// scans cut short or with junk restart markers, a deflate strip failing its checksum, TIFF
// directories that loop, and TIFF headers declaring far more than their files hold, refused at a
// small peak memory.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "bad_input.h"
#include "file_io.h"
#include "jpeg_damage.h"
#include "tiff_bytes.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::write_bytes;

using test::BadInput;

// JPEG AND TIFF DATA ---------------------------------------------------------------------------

// A stack of 8 JPEG slices written by OpenCV with a restart marker after every 8x8 block; slice
// 5 is replaced by `damage` of itself.
void write_jpeg_stack(
    const fs::path& dir,
    const std::function<std::vector<unsigned char>(std::vector<unsigned char>)>& damage) {
  fs::create_directories(dir);
  for (int z = 0; z < 8; ++z) {
    cv::Mat slice(48, 64, CV_8UC1);
    cv::randu(slice, 0, 255);
    slice(cv::Rect(32 - 2 * z, 24 - 2 * z, 1 + 4 * z, 1 + 4 * z)).setTo(250);
    std::vector<unsigned char> bytes;
    ASSERT_TRUE(cv::imencode(".jpg", slice, bytes, {cv::IMWRITE_JPEG_RST_INTERVAL, 1}));
    if (z == 5) bytes = damage(bytes);
    write_bytes((dir / ("slice_" + std::to_string(z) + ".jpg")).string(),
                std::string(bytes.begin(), bytes.end()));
  }
}

TEST_F(BadInput, JpegWithItsScanCutShortAndClosed) {
  // libjpeg fills the missing part with grey and only warns: OpenCV returned such slices.
  write_jpeg_stack(dir_ / "jpegs", [](std::vector<unsigned char> jpeg) {
    const test::ScanData scan = test::first_scan_data(jpeg);
    return test::cut_in_scan(jpeg, (scan.end - scan.begin) / 2);
  });
  expect_refused("extract jpegs -t 128" + kOutputs, "jpegs/slice_5.jpg",
                 "cannot decode JPEG: Corrupt JPEG data: ");
}

TEST_F(BadInput, JpegWithJunkRestartMarkers) {
  write_jpeg_stack(dir_ / "jpegs", test::renumber_restart_marker);
  expect_refused("extract jpegs -t 128" + kOutputs, "jpegs/slice_5.jpg",
                 "cannot decode JPEG: Corrupt JPEG data: found marker 0x");
  write_jpeg_stack(dir_ / "more_jpegs", [](const std::vector<unsigned char>& jpeg) {
    return test::insert_restart_markers(jpeg, 20);
  });
  expect_refused("extract more_jpegs -t 128" + kOutputs, "more_jpegs/slice_5.jpg",
                 "cannot decode JPEG: Corrupt JPEG data: ");
}

// A deflate page of 12x10 samples in one strip.
test::TiffPageBytes deflate_page(unsigned char value) {
  return {12, 10, 8, 8, 0, 0, 0, {test::zlib_compressed(std::vector<unsigned char>(120, value))}};
}

TEST_F(BadInput, TiffDeflateStripFailingItsChecksum) {
  std::vector<test::TiffPageBytes> pages;
  for (int z = 0; z < 8; ++z) pages.push_back(deflate_page(z > 1 && z < 6 ? 200 : 0));
  pages[5].chunks[0].back() ^= 0x01;  // the last byte of the Adler-32 checksum
  const std::vector<unsigned char> tiff = test::tiff_file_bytes(pages);
  write_bytes(dir_ / "stack.tif", std::string(tiff.begin(), tiff.end()));
  expect_refused("extract stack.tif -t 128" + kOutputs, "stack.tif",
                 "page 6: strip 0: corrupt deflate data (zlib: incorrect data check)");
}

TEST_F(BadInput, TiffWhoseDirectoriesLoop) {
  // Three pages, the third's link to a next directory leading back to the first: read forever
  // by a reader that does not look for loops.
  const test::TiffPageBytes page{12, 10, 8, 1, 0, 0, 0, {std::vector<unsigned char>(120, 200)}};
  std::vector<unsigned char> tiff = test::tiff_file_bytes({page, page, page});
  test::put_tiff_u32(tiff, test::tiff_next_link(tiff, 2), test::tiff_directory_offset(tiff, 0));
  write_bytes(dir_ / "loop.tif", std::string(tiff.begin(), tiff.end()));
  expect_refused("extract loop.tif -t 128" + kOutputs, "loop.tif",
                 "cannot read the directory of page 6: it is an earlier page's (the directories "
                 "loop)");
}

// Lying headers must cost what their files hold, not what they declare. The whole process,
// shared libraries included, takes about 60 MB.
constexpr long kFarUnder200MiB = 200 * 1024;

TEST_F(BadInput, TiffWithTilesFarLargerThanItsImage) {
  // ~150 bytes declaring one 65536x65536 tile for a 12x10 image: 4.2 GB and 19 s before.
  const std::vector<unsigned char> tiff = test::tiff_file_bytes(
      {{12, 10, 8, 8, 0, 65536, 65536, {test::zlib_compressed(std::vector<unsigned char>(200))}}});
  write_bytes(dir_ / "tiles.tif", std::string(tiff.begin(), tiff.end()));
  const long peak = refused_peak_memory_kib(
      {"extract", "tiles.tif", "-t", "10", "-o", "previous.ply", "--image", "previous.png",
       "--stats", "previous.json", "-q"},
      "tiles.tif", "page 1: its 65536x65536 tiles are far larger than the 12x10 image");
  EXPECT_GT(peak, 0);
  EXPECT_LT(peak, kFarUnder200MiB) << "KiB at peak";
}

TEST_F(BadInput, TinyDeflateTiffDeclaringAHugePage) {
  // 30000x30000 samples declared by a 17-byte strip: std::bad_alloc after 1-1.9 GB before.
  const std::vector<unsigned char> tiff = test::tiff_file_bytes(
      {{30000, 30000, 8, 8, 0, 0, 0, {test::zlib_compressed(std::vector<unsigned char>(1000))}}});
  write_bytes(dir_ / "page.tif", std::string(tiff.begin(), tiff.end()));
  const long peak = refused_peak_memory_kib(
      {"extract", "page.tif", "-t", "10", "-o", "previous.ply", "--image", "previous.png",
       "--stats", "previous.json", "-q"},
      "page.tif",
      "page 1: strip 0 declares 900000000 bytes (30000 rows of 30000 8-bit unsigned samples) "
      "but stores 17 bytes of deflate data, which decode to at most 1032 times as many");
  EXPECT_GT(peak, 0);
  EXPECT_LT(peak, kFarUnder200MiB) << "KiB at peak";
}

}  // namespace
}  // namespace mvox
