// TIFF stacks (src/read/tiff/tiff_stack_source.h) refused before any slice is read, naming the
// file and the 1-based page: colour, palette, 64-bit float and pages unlike the first (in one
// file or across files), files cut anywhere, and a strip moved past the end of the file.
#include <tiffio.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "gtest/gtest.h"
#include "read/input_format.h"
#include "read/tiff/tiff_stack_source.h"
#include "tiff_stack_files.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::error_of;
using test::ScratchDirectory;
using test::tiff_stack_files::kDepth;
using test::tiff_stack_files::kHeight;
using test::tiff_stack_files::kLayouts;
using test::tiff_stack_files::kWidth;
using test::tiff_stack_files::write_page;
using test::tiff_stack_files::write_stack;

// A stack of 5 good 8-bit pages in which page `bad_page` (0-based) is written by `write_bad`.
void write_stack_with_bad_page(const std::string& path, int bad_page,
                               const std::function<void(TIFF*)>& write_bad) {
  const std::vector<std::uint8_t> page(kWidth * kHeight, 100);
  TIFF* tiff = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tiff, nullptr);
  for (int p = 0; p < 5; ++p) {
    if (p == bad_page) {
      write_bad(tiff);
    } else {
      write_page(tiff, page.data(), kWidth, kHeight, 8, SAMPLEFORMAT_UINT, 1, kLayouts[0]);
    }
  }
  TIFFClose(tiff);
}

TEST(TiffStack, RefusesBadPagesNamingFileAndPage) {
  ScratchDirectory dir;
  const std::vector<std::uint8_t> rgb(kWidth * kHeight * 3, 50);
  write_stack_with_bad_page(dir / "colour.tif", 2, [&](TIFF* tiff) {
    write_page(tiff, rgb.data(), kWidth, kHeight, 8, SAMPLEFORMAT_UINT, 3, kLayouts[0]);
  });
  EXPECT_CONTAINS(error_of([&] { TiffStackSource source({dir / "colour.tif"}); }),
                  dir / "colour.tif: page 3 is a colour or multi-sample image (3 samples");

  const std::vector<std::uint8_t> small(20 * kHeight, 1);
  write_stack_with_bad_page(dir / "size.tif", 1, [&](TIFF* tiff) {
    write_page(tiff, small.data(), 20, kHeight, 8, SAMPLEFORMAT_UINT, 1, kLayouts[0]);
  });
  EXPECT_CONTAINS(error_of([&] { TiffStackSource source({dir / "size.tif"}); }),
                  dir /
                      "size.tif: page 2 is 20x29 8-bit unsigned, expected 37x29 8-bit "
                      "unsigned like page 1");

  const std::vector<std::uint16_t> wide(kWidth * kHeight, 1);
  write_stack_with_bad_page(dir / "type.tif", 4, [&](TIFF* tiff) {
    write_page(tiff, wide.data(), kWidth, kHeight, 16, SAMPLEFORMAT_UINT, 1, kLayouts[0]);
  });
  EXPECT_CONTAINS(error_of([&] { TiffStackSource source({dir / "type.tif"}); }),
                  dir / "type.tif: page 5 is 37x29 16-bit unsigned, expected 37x29 8-bit");

  const std::vector<double> doubles(kWidth * kHeight, 1);
  write_stack_with_bad_page(dir / "double.tif", 0, [&](TIFF* tiff) {
    write_page(tiff, doubles.data(), kWidth, kHeight, 64, SAMPLEFORMAT_IEEEFP, 1, kLayouts[0]);
  });
  EXPECT_CONTAINS(error_of([&] { TiffStackSource source({dir / "double.tif"}); }),
                  dir / "double.tif: page 1 has 64-bit float samples");

  write_stack_with_bad_page(dir / "palette.tif", 1, [&](TIFF* tiff) {
    const std::vector<std::uint16_t> map(256, 0);
    const std::vector<std::uint8_t> indices(kWidth * kHeight, 1);
    // The colour map goes in after BitsPerSample: libtiff copies 2^BitsPerSample entries of it.
    write_page(tiff, indices.data(), kWidth, kHeight, 8, SAMPLEFORMAT_UINT, 1, kLayouts[0],
               [&](TIFF* t) {
                 TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_PALETTE);
                 TIFFSetField(t, TIFFTAG_COLORMAP, map.data(), map.data(), map.data());
               });
  });
  EXPECT_CONTAINS(error_of([&] { TiffStackSource source({dir / "palette.tif"}); }),
                  dir / "palette.tif: page 2 is a palette colour image");

  // Across files, the first page of the first file sets the format.
  fs::create_directories(dir / "mixed_sizes");
  write_stack_with_bad_page(dir / "mixed_sizes/a.tif", -1, {});
  write_stack_with_bad_page(dir / "mixed_sizes/b.tif", 3, [&](TIFF* tiff) {
    write_page(tiff, small.data(), 20, kHeight, 8, SAMPLEFORMAT_UINT, 1, kLayouts[0]);
  });
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "mixed_sizes"}, std::nullopt); }),
                  dir / "mixed_sizes/b.tif: page 4 is 20x29 8-bit unsigned, expected 37x29 "
                        "8-bit unsigned like page 1 of " +
                      (dir / "mixed_sizes/a.tif"));
}

// Rewrites, in place, the offset of the first strip of page `page` (0-based) of a little-endian
// classic TIFF written by libtiff (StripOffsets as LONGs), which libtiff's API cannot set.
void move_first_strip(const std::string& path, int page, std::uint32_t new_offset) {
  TIFF* tiff = TIFFOpen(path.c_str(), "r");
  ASSERT_NE(tiff, nullptr);
  ASSERT_TRUE(TIFFSetDirectory(tiff, static_cast<tdir_t>(page)));
  const std::uint64_t directory = TIFFCurrentDirOffset(tiff);
  TIFFClose(tiff);

  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  auto read_u16 = [&](std::uint64_t at) {
    unsigned char b[2];
    file.seekg(static_cast<std::streamoff>(at));
    file.read(reinterpret_cast<char*>(b), 2);
    return static_cast<std::uint16_t>(b[0] | b[1] << 8);
  };
  auto read_u32 = [&](std::uint64_t at) {
    unsigned char b[4];
    file.seekg(static_cast<std::streamoff>(at));
    file.read(reinterpret_cast<char*>(b), 4);
    return static_cast<std::uint32_t>(b[0] | b[1] << 8 | b[2] << 16 |
                                      static_cast<std::uint32_t>(b[3]) << 24);
  };
  ASSERT_EQ(read_u16(0), 0x4949u) << "expected a little-endian (II) TIFF";
  const std::uint16_t entries = read_u16(directory);
  for (std::uint16_t i = 0; i < entries; ++i) {
    const std::uint64_t entry = directory + 2 + 12u * i;
    if (read_u16(entry) != TIFFTAG_STRIPOFFSETS) continue;
    ASSERT_EQ(read_u16(entry + 2), TIFF_LONG);
    // One strip: the offset is in the entry itself; several: the entry points at the array.
    const std::uint64_t at = read_u32(entry + 4) == 1 ? entry + 8 : read_u32(entry + 8);
    const unsigned char b[4] = {
        static_cast<unsigned char>(new_offset), static_cast<unsigned char>(new_offset >> 8),
        static_cast<unsigned char>(new_offset >> 16), static_cast<unsigned char>(new_offset >> 24)};
    file.seekp(static_cast<std::streamoff>(at));
    file.write(reinterpret_cast<const char*>(b), 4);
    ASSERT_TRUE(file.good());
    return;
  }
  FAIL() << "no StripOffsets in directory " << page;
}

TEST(TiffStack, RefusesTruncatedFilesBeforeReadingASlice) {
  const std::vector<std::uint16_t> samples =
      test::phantom_samples<std::uint16_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  write_stack(dir / "whole.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[0]);
  const auto size = fs::file_size(dir / "whole.tif");
  // Cut in the middle (later pages and their directories gone), just before the end (the last
  // directory damaged), and to a bare 8-byte header.
  for (const std::uintmax_t keep : {size / 2, size - 6, std::uintmax_t{8}}) {
    SCOPED_TRACE(keep);
    fs::copy_file(dir / "whole.tif", dir / "cut.tif", fs::copy_options::overwrite_existing);
    fs::resize_file(dir / "cut.tif", keep);
    const std::string message = error_of([&] { TiffStackSource source({dir / "cut.tif"}); });
    EXPECT_EQ(message.rfind(dir / "cut.tif: ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }

  // The first strip of page 3 moved past the end of an otherwise intact file.
  fs::copy_file(dir / "whole.tif", dir / "strip.tif");
  move_first_strip(dir / "strip.tif", 2, static_cast<std::uint32_t>(size + 1000));
  EXPECT_CONTAINS(error_of([&] { TiffStackSource source({dir / "strip.tif"}); }),
                  dir / "strip.tif: page 3: strip 0 ends at byte ");
}

}  // namespace
}  // namespace mvox
