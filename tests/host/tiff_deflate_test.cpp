// Deflate pages of TIFF stacks: mvox checks every strip's and tile's zlib checksum, also where
// libtiff stops short of it, and names the page and the strip or tile that fails it; and every
// sample type, byte order, predictor (src/read/tiff/tiff_predictor.h), fill order and layout
// reads back as written.
#include <tiffio.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "file_io.h"
#include "gtest/gtest.h"
#include "tiff_bytes.h"
#include "tiff_stack_files.h"
#include "volume_samples.h"

namespace mvox {
namespace {

using test::error_of;
using test::ScratchDirectory;
using test::write_bytes;
using test::tiff_stack_files::filled;
using test::tiff_stack_files::kDepth;
using test::tiff_stack_files::kHeight;
using test::tiff_stack_files::kLayouts;
using test::tiff_stack_files::kWidth;
using test::tiff_stack_files::Layout;
using test::tiff_stack_files::read_stack;
using test::tiff_stack_files::write_stack;

// Flips the last stored byte (the end of the zlib checksum) of strip or tile `index` of page
// `page` (0-based), which libtiff's deflate decoder never looks at.
void damage_checksum(const std::string& path, int page, std::uint32_t index) {
  TIFF* tiff = TIFFOpen(path.c_str(), "r");
  ASSERT_NE(tiff, nullptr);
  ASSERT_TRUE(TIFFSetDirectory(tiff, static_cast<tdir_t>(page)));
  const std::uint64_t end = TIFFGetStrileOffset(tiff, index) + TIFFGetStrileByteCount(tiff, index);
  TIFFClose(tiff);
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekg(static_cast<std::streamoff>(end - 1));
  const char last = static_cast<char>(file.get());
  file.seekp(static_cast<std::streamoff>(end - 1));
  file.put(static_cast<char>(last ^ 0x40));
  ASSERT_TRUE(file.good());
}

TEST(TiffStack, DeflateDataFailingTheirChecksumAreRefusedNamingPageAndStripOrTile) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  // One row per strip: strip 20 of page 3.
  write_stack(dir / "striped.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[1]);
  damage_checksum(dir / "striped.tif", 2, 20);
  EXPECT_EQ(
      error_of([&] { read_stack<std::uint8_t>({dir / "striped.tif"}); }),
      dir / "striped.tif: page 3: strip 20: corrupt deflate data (zlib: incorrect data check)");

  // Tiled, Adobe's and the old deflate code alike; tile 3 of page 6.
  for (const std::uint16_t compression : {COMPRESSION_ADOBE_DEFLATE, COMPRESSION_DEFLATE}) {
    SCOPED_TRACE(compression);
    const Layout tiled{"tiled 16x16, deflate", true, 0, compression};
    write_stack(dir / "tiled.tif", samples, kWidth, kHeight, 0, kDepth, tiled);
    EXPECT_EQ(read_stack<std::uint8_t>({dir / "tiled.tif"}), samples);
    damage_checksum(dir / "tiled.tif", 5, 3);
    EXPECT_EQ(error_of([&] { read_stack<std::uint8_t>({dir / "tiled.tif"}); }),
              dir / "tiled.tif: page 6: tile 3: corrupt deflate data (zlib: incorrect data check)");
  }
}

TEST(TiffStack, ChecksumIsCheckedWhereLibtiffStopsShortOfIt) {
  // A strip whose stream holds more rows than the strip (some writers store whole strips at
  // the bottom of a page): libtiff decodes the rows it wants and stops (libdeflate's
  // "insufficient space", which it accepts on purpose), never reaching the checksum. Where the
  // stream ends with the strip, libtiff does check it (tested above with mvox's message).
  std::vector<unsigned char> rows(kWidth * (kHeight + 3));
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<unsigned char>(i * 7);
  std::vector<unsigned char> stream = test::zlib_compressed(rows);
  stream.back() ^= 0x40;
  ScratchDirectory dir;
  write_bytes(
      dir / "long.tif",
      test::tiff_file_bytes({{kWidth, kHeight, 8, COMPRESSION_ADOBE_DEFLATE, 0, 0, 0, {stream}}}));
  TIFF* tiff = TIFFOpen((dir / "long.tif").c_str(), "r");
  ASSERT_NE(tiff, nullptr);
  std::vector<unsigned char> strip(kWidth * kHeight);
  EXPECT_EQ(TIFFReadEncodedStrip(tiff, 0, strip.data(), static_cast<tmsize_t>(strip.size())),
            static_cast<tmsize_t>(strip.size()))
      << "libtiff no longer takes this strip: the case needs another example";
  TIFFClose(tiff);
  EXPECT_EQ(error_of([&] { read_stack<std::uint8_t>({dir / "long.tif"}); }),
            dir / "long.tif: page 1: strip 0: corrupt deflate data (zlib: incorrect data check)");
  // A whole stream, checksum right, that holds fewer rows than the strip.
  write_bytes(dir / "short.tif",
              test::tiff_file_bytes({{kWidth,
                                      kHeight,
                                      8,
                                      COMPRESSION_ADOBE_DEFLATE,
                                      0,
                                      0,
                                      0,
                                      {test::zlib_compressed(filled(kWidth * 20, 9))}}}));
  EXPECT_EQ(error_of([&] { read_stack<std::uint8_t>({dir / "short.tif"}); }),
            dir /
                "short.tif: page 1: strip 0: its deflate data decode to 740 bytes, fewer than "
                "the 1073 it holds");
  // The same strip with its checksum intact is read.
  stream.back() ^= 0x40;
  write_bytes(
      dir / "long.tif",
      test::tiff_file_bytes({{kWidth, kHeight, 8, COMPRESSION_ADOBE_DEFLATE, 0, 0, 0, {stream}}}));
  // (libtiff with libdeflate leaves the last bytes of such a strip zero: mvox has libtiff
  // decode deflate with zlib.)
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "long.tif"}),
            std::vector<std::uint8_t>(rows.begin(), rows.begin() + kWidth * kHeight));
}

// Deflate pages are inflated by mvox and finished by tiff_predictor.h (libtiff only for the
// floating-point predictor): every sample type, byte order, predictor, fill order and layout
// must come out as written.
template <typename T>
void expect_deflate_round_trips(SampleType type) {
  const std::vector<T> samples = test::phantom_samples<T>(kWidth, kHeight, kDepth);
  std::vector<std::uint16_t> predictors = {PREDICTOR_NONE, PREDICTOR_HORIZONTAL};
  if (type == SampleType::f32) predictors.push_back(PREDICTOR_FLOATINGPOINT);
  const Layout layouts[] = {
      kLayouts[1],
      {"tiled 16x16, deflate", true, 0, COMPRESSION_DEFLATE},
      {"striped, 5 rows per strip, deflate", false, 5, COMPRESSION_ADOBE_DEFLATE}};
  ScratchDirectory dir;
  for (const char* mode : {"wl", "wb"}) {
    for (const std::uint16_t predictor : predictors) {
      for (const std::uint16_t fill_order : {FILLORDER_MSB2LSB, FILLORDER_LSB2MSB}) {
        // libtiff 4.5 does not read back its own big-endian floating-point predictor files
        // (the floats come out byte-swapped), a case mvox leaves to libtiff.
        if (predictor == PREDICTOR_FLOATINGPOINT && mode[1] == 'b') continue;
        for (const Layout& layout : layouts) {
          SCOPED_TRACE(std::string(sample_type_name(type)) + ", " + mode + ", predictor " +
                       std::to_string(predictor) + ", fill order " + std::to_string(fill_order) +
                       ", " + layout.name);
          write_stack(
              dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, layout,
              [&](TIFF* tiff) {
                TIFFSetField(tiff, TIFFTAG_PREDICTOR, predictor);
                TIFFSetField(tiff, TIFFTAG_FILLORDER, fill_order);
              },
              mode);
          EXPECT_EQ(read_stack<T>({dir / "stack.tif"}), samples);
        }
      }
    }
  }
}

TEST(TiffStack, DeflateRoundTripsInEveryByteOrderPredictorAndFillOrder) {
  expect_deflate_round_trips<std::uint8_t>(SampleType::u8);
  expect_deflate_round_trips<std::uint16_t>(SampleType::u16);
  expect_deflate_round_trips<std::int16_t>(SampleType::i16);
  expect_deflate_round_trips<float>(SampleType::f32);
}

}  // namespace
}  // namespace mvox
