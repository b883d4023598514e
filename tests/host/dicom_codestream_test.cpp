// Compressed DICOM pixel data checked against the header before GDCM decodes it
// (src/read/dicom/dicom_codestream.h): codestreams whose size, end marker or RLE segments
// disagree with the header, and frames too short for their declared size, are refused naming
// the file.
#include <gtest/gtest.h>

#include <cstddef>
#include <functional>
#include <string>

#include "command_runner.h"
#include "dicom_series.h"
#include "dicom_writer.h"
#include "file_io.h"

namespace mvox {
namespace {

using test::DicomSliceSpec;
using test::read_bytes;
using test::ScratchDirectory;
using test::write_bytes;
using test::dicom_series::expect_error;
using test::dicom_series::open_series;
using test::dicom_series::pattern;

// A 33x24 image of 16-bit samples, uncompressed: the file the codestream tests recode.
void write_plain_33x24(const std::string& path) {
  DicomSliceSpec spec;
  spec.width = 33;
  spec.height = 24;
  spec.stored = pattern(33, 24, 0);
  test::write_dicom(path, spec);
}

// GDCM sizes its output from the DICOM header and trusts the codestream to agree; where they
// disagree it corrupts the heap or aborts. These files would crash mvox without the checks in
// dicom_codestream.cpp.
TEST(DicomSeries, CodestreamsThatDisagreeWithTheHeaderAreRefusedBeforeDecoding) {
  ScratchDirectory dir;
  write_plain_33x24(dir / "plain.dcm");
  struct Case {
    const char* syntax;
    std::function<bool(std::string&)> corrupt;  // false when the place to corrupt is missing
    const char* words;
  };
  auto at_marker = [](std::string& bytes, const std::string& marker, std::size_t offset,
                      char value) {
    const std::size_t at = bytes.find(marker);
    if (at == std::string::npos) return false;
    bytes[at + offset] = value;
    return true;
  };
  const Case cases[] = {
      // SIZ: Xsiz is the 4 bytes at offset 8 from SOC; 33 becomes 0x0121 = 289.
      {test::kJpeg2000LosslessUid,
       [&](std::string& b) { return at_marker(b, std::string("\xFF\x4F\xFF\x51", 4), 10, 1); },
       "its JPEG 2000 codestream is 289x24, the DICOM header says 33x24"},
      // The end of codestream marker, FFD9, gone: GDCM's JPEG 2000 codec asserts on that.
      {test::kJpeg2000LosslessUid,
       [&](std::string& b) {
         const std::size_t at = b.rfind(std::string("\xFF\xD9", 2));
         if (at == std::string::npos) return false;
         b[at + 1] = 0;
         return true;
       },
       "its JPEG 2000 codestream does not end with FFD9"},
      // SOF55: height at offset 5 from the marker; 24 becomes 0x0118 = 280.
      {test::kJpegLsLosslessUid,
       [&](std::string& b) { return at_marker(b, std::string("\xFF\xF7", 2), 5, 1); },
       "its JPEG-LS codestream is 33x280, the DICOM header says 33x24"},
      // SOF3 (lossless): width at offset 7 from the marker; 33 becomes 0x0221 = 545.
      {test::kJpegLosslessUid,
       [&](std::string& b) { return at_marker(b, std::string("\xFF\xC3", 2), 7, 2); },
       "its JPEG codestream is 545x24, the DICOM header says 33x24"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.syntax) + ": " + c.words);
    ScratchDirectory one;
    ASSERT_TRUE(test::recode(dir / "plain.dcm", one / "image.dcm", c.syntax));
    std::string bytes = read_bytes(one / "image.dcm");
    ASSERT_TRUE(c.corrupt(bytes));
    write_bytes(one / "image.dcm", bytes);
    expect_error([&] { open_series(one.path().string()); }, one / "image.dcm", c.words);
  }
  // RLE: 16-bit samples need two segments; the header says one.
  ScratchDirectory rle;
  ASSERT_TRUE(test::recode(dir / "plain.dcm", rle / "image.dcm", test::kRleLosslessUid));
  std::string bytes = read_bytes(rle / "image.dcm");
  const std::size_t header = bytes.find(std::string("\x02\x00\x00\x00\x40\x00\x00\x00", 8));
  ASSERT_NE(header, std::string::npos);
  bytes[header] = 1;
  write_bytes(rle / "image.dcm", bytes);
  expect_error([&] { open_series(rle.path().string()); }, rle / "image.dcm",
               "its RLE header has 1 segments, 16-bit samples need 2");
}

// A header that declares a far larger image than its compressed frame can decode to (at the
// codec's largest ratio, compression_bounds.h) is refused before GDCM allocates for it.
TEST(DicomSeries, CompressedFramesTooShortForTheirDeclaredSizeAreRefused) {
  ScratchDirectory dir;
  write_plain_33x24(dir / "plain.dcm");
  for (const char* syntax : {test::kRleLosslessUid, test::kJpegLosslessUid}) {
    SCOPED_TRACE(syntax);
    ScratchDirectory one;
    ASSERT_TRUE(test::recode(dir / "plain.dcm", one / "image.dcm", syntax));
    std::string bytes = read_bytes(one / "image.dcm");
    // Rows (0028,0010) and Columns (0028,0011), explicit VR US: 4000 each, 32 MB a frame.
    for (const char element : {'\x10', '\x11'}) {
      const std::size_t at =
          bytes.find(std::string("\x28\x00", 2) + element + std::string("\x00US\x02\x00", 5));
      ASSERT_NE(at, std::string::npos);
      bytes[at + 8] = static_cast<char>(4000 & 0xff);
      bytes[at + 9] = static_cast<char>(4000 >> 8);
    }
    write_bytes(one / "image.dcm", bytes);
    expect_error([&] { open_series(one.path().string()); }, one / "image.dcm",
                 "bytes of compressed data cannot hold a 4000x4000 frame of 32000000 bytes");
  }
}

}  // namespace
}  // namespace mvox
