// What a TIFF page may cost: headers declaring more samples than their data can decode to, and
// tiles far larger than the image, are refused before anything is allocated for them; the slice
// buffer comes with the first slice, and working_bytes() adds up the buffers of the largest page.
#include <tiffio.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "file_io.h"
#include "gtest/gtest.h"
#include "read/tiff/tiff_stack_source.h"
#include "read/zlib_stream_check.h"
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

TEST(TiffStack, HeadersDeclaringMoreThanTheirDataCanHoldAreRefusedBeforeAnySlice) {
  ScratchDirectory dir;
  const auto refusal = [&](const test::TiffPageBytes& page) {
    write_bytes(dir / "lying.tif", test::tiff_file_bytes({page}));
    return error_of([&] { TiffStackSource source({dir / "lying.tif"}); });
  };
  const std::vector<unsigned char> tiny_deflate = test::zlib_compressed(filled(100, 7));
  const std::string lying = dir / "lying.tif: page 1";

  test::TiffPageBytes page{30000, 30000, 8, COMPRESSION_ADOBE_DEFLATE, 0, 0, 0, {tiny_deflate}};
  EXPECT_EQ(refusal(page),
            lying + ": strip 0 declares 900000000 bytes (30000 rows of 30000 " +
                "8-bit unsigned samples) but stores " + std::to_string(tiny_deflate.size()) +
                " bytes of deflate data, which decode to at most 1032 times as many");

  // Uncompressed: exactly.
  // (libtiff itself replaces the byte counts when the first two strips differ.)
  page = {200, 300, 16, COMPRESSION_NONE, 100, 0, 0, {filled(40000, 1), filled(40000, 1), {}}};
  page.chunks[2] = filled(39999, 1);
  EXPECT_EQ(refusal(page), lying + ": strip 2 declares 40000 bytes (100 rows of 200 16-bit " +
                               "unsigned samples) but stores 39999 bytes of uncompressed data");

  // PackBits, tiled.
  page = {1000, 1000, 8, COMPRESSION_PACKBITS, 0, 1024, 1024, {filled(100, 0x81)}};
  EXPECT_EQ(refusal(page), lying + ": tile 0 declares 1048576 bytes (1024x1024 8-bit unsigned " +
                               "samples) but stores 100 bytes of PackBits data, which decode to " +
                               "at most 64 times as many");

  // Each of 20000 strips is within what a stream's overhead allows, but not all of them.
  page = {20000, 20000, 8, COMPRESSION_ADOBE_DEFLATE, 1, 0, 0, {}};
  page.chunks.assign(20000, tiny_deflate);
  EXPECT_EQ(refusal(page),
            lying + " declares 400000000 bytes (20000x20000 8-bit unsigned " +
                "samples) in 20000 strips but stores " +
                std::to_string(20000 * tiny_deflate.size()) +
                " bytes of deflate data, which decode to at most 1032 times as many");

  // Sizes whose products would wrap round 2^64 are refused, here by libtiff already.
  page = {0xffffffff, 0xffffffff, 16, COMPRESSION_ADOBE_DEFLATE, 0, 0, 0, {tiny_deflate}};
  EXPECT_EQ(refusal(page).rfind(dir / "lying.tif: ", 0), 0u);
}

TEST(TiffStack, TilesFarLargerThanTheImageAreRefusedCommonOnesAreRead) {
  ScratchDirectory dir;
  // 12x10 samples in a 256x256 tile, as writers with one fixed tile size store small images.
  std::vector<unsigned char> tile(256 * 256, 0xee);
  std::vector<std::uint8_t> expected;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x)
      expected.push_back(tile[y * 256 + x] = static_cast<unsigned char>(y * 12 + x));
  write_bytes(
      dir / "fixed.tif",
      test::tiff_file_bytes(
          {{12, 10, 8, COMPRESSION_ADOBE_DEFLATE, 0, 256, 256, {test::zlib_compressed(tile)}}}));
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "fixed.tif"}), expected);
  // 4096x4096 whatever the image.
  write_bytes(
      dir / "large.tif",
      test::tiff_file_bytes({{12,
                              10,
                              8,
                              COMPRESSION_ADOBE_DEFLATE,
                              0,
                              4096,
                              4096,
                              {test::zlib_compressed(std::vector<unsigned char>(4096 * 4096))}}}));
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "large.tif"}), std::vector<std::uint8_t>(120, 0));

  // A ~250-byte file declaring 65536x65536 tiles: 4 GiB for one tile.
  write_bytes(dir / "huge.tif", test::tiff_file_bytes({{12,
                                                        10,
                                                        8,
                                                        COMPRESSION_ADOBE_DEFLATE,
                                                        0,
                                                        65536,
                                                        65536,
                                                        {test::zlib_compressed(filled(200, 3))}}}));
  EXPECT_EQ(error_of([&] { TiffStackSource source({dir / "huge.tif"}); }),
            dir /
                "huge.tif: page 1: its 65536x65536 tiles are far larger than the 12x10 image (a "
                "tile may hold the image rounded up to multiples of 16, or 4096x4096 samples)");
  // Just over the rule on a large image: one tile more than the image rounded up to 16 rows.
  write_bytes(
      dir / "tall.tif",
      test::tiff_file_bytes({{5000, 5000, 8, COMPRESSION_NONE, 0, 5008, 5024, {filled(100, 0)}}}));
  EXPECT_CONTAINS(error_of([&] { TiffStackSource source({dir / "tall.tif"}); }),
                  "page 1: its 5008x5024 tiles are far larger than the 5000x5000 image");
}

TEST(TiffStack, BuffersComeWithTheFirstSliceAndWorkingBytesBoundThem) {
  ScratchDirectory dir;
  // Zstandard has no expansion bound: a header declaring 2^31 x 2^30 16-bit samples passes
  // the directory walk, which allocates nothing for it; the slice buffer is asked for with the
  // first slice, and fails as an mvox::Error, not a std::bad_alloc.
  if (!TIFFIsCODECConfigured(COMPRESSION_ZSTD)) GTEST_SKIP() << "this libtiff has no Zstandard";
  write_bytes(dir / "zstd.tif",
              test::tiff_file_bytes(
                  {{0x80000000u, 0x40000000u, 16, COMPRESSION_ZSTD, 0, 0, 0, {filled(64, 1)}}}));
  TiffStackSource source({dir / "zstd.tif"});
  // The slice, libtiff's buffer for the stored strip, and the strip's place (offset and count).
  EXPECT_EQ(source.working_bytes(), (std::uint64_t{1} << 62) + 1024 + 16);
  SliceView slice;
  EXPECT_EQ(error_of([&] { source.next_slice(&slice); }),
            dir /
                "zstd.tif: out of memory: cannot allocate 4611686018427387904 bytes for the "
                "2147483648x1073741824 slice");
}

TEST(TiffStack, WorkingBytesAddUpTheBuffersOfTheLargestPage) {
  const std::vector<std::uint16_t> samples =
      test::phantom_samples<std::uint16_t>(kWidth, kHeight, kDepth);
  const std::uint64_t slice = kWidth * kHeight * 2;
  ScratchDirectory dir;
  // The largest stored strip or tile, and the most strips or tiles of a page, from libtiff.
  const auto largest_chunk = [](const std::string& path, std::uint64_t* most_chunks) {
    std::uint64_t largest = 0;
    *most_chunks = 0;
    TIFF* tiff = TIFFOpen(path.c_str(), "r");
    do {
      const std::uint32_t count =
          TIFFIsTiled(tiff) ? TIFFNumberOfTiles(tiff) : TIFFNumberOfStrips(tiff);
      *most_chunks = std::max<std::uint64_t>(*most_chunks, count);
      for (std::uint32_t i = 0; i < count; ++i)
        largest = std::max(largest, TIFFGetStrileByteCount(tiff, i));
    } while (TIFFReadDirectory(tiff));
    TIFFClose(tiff);
    return largest;
  };
  for (const Layout& layout : kLayouts) {
    SCOPED_TRACE(layout.name);
    write_stack(dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, layout);
    TiffStackSource source({dir / "stack.tif"});
    std::uint64_t most_chunks = 0;
    const std::uint64_t chunk = largest_chunk(dir / "stack.tif", &most_chunks);
    // The slice, a tile, and the places (offset and byte count) of the page's strips or tiles.
    std::uint64_t expected = slice + (layout.tiled ? 16 * 16 * 2 : 0) + 16 * most_chunks;
    if (layout.compression == COMPRESSION_ADOBE_DEFLATE)
      expected += chunk + ZlibStreamCheck::kWorkingBytes;
    else if (layout.compression != COMPRESSION_NONE)
      expected += (chunk + 1023) / 1024 * 1024;
    EXPECT_EQ(source.working_bytes(), expected);
    EXPECT_EQ(test::read_samples<std::uint16_t>(source), samples);
  }
}

}  // namespace
}  // namespace mvox
