// TIFF stacks (tiff_stack_source.h): multi-page files written here with libtiff, striped and
// tiled, compressed or not, for every page type; the samples must be the phantom's, and the
// mesh the one from the same slices as separate image files (read by OpenCV) or a raw volume.
// Refusals name the file and the 1-based page.
#include <tiffio.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "command_runner.h"
#include "error.h"
#include "error_capture.h"
#include "gtest/gtest.h"
#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "read/image_stack/image_stack_source.h"
#include "read/input_format.h"
#include "read/raw/raw_volume_source.h"
#include "read/tiff/tiff_stack_source.h"
#include "read/zlib_stream_check.h"
#include "tiff_bytes.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::error_of;

using test::ScratchDirectory;

// Not multiples of the 16-pixel tiles, so that edge tiles are partly outside the image.
constexpr std::uint32_t kWidth = 37, kHeight = 29, kDepth = 7;

struct Layout {
  const char* name;
  bool tiled;
  std::uint32_t rows_per_strip;  // striped pages
  std::uint16_t compression;
};

constexpr Layout kLayouts[] = {
    {"striped, 4 rows per strip", false, 4, COMPRESSION_NONE},
    {"striped, one row per strip, deflate", false, 1, COMPRESSION_ADOBE_DEFLATE},
    {"tiled 16x16", true, 0, COMPRESSION_NONE},
    {"tiled 16x16, LZW", true, 0, COMPRESSION_LZW},
};

template <typename T>
std::uint16_t sample_format() {
  if constexpr (std::is_floating_point_v<T>) return SAMPLEFORMAT_IEEEFP;
  if constexpr (std::is_signed_v<T>) return SAMPLEFORMAT_INT;
  return SAMPLEFORMAT_UINT;
}

// Writes one page of `samples_per_pixel` x `bits` samples (pixels interleaved) and ends its
// directory; `extra` may set more tags first.
void write_page(TIFF* tiff, const void* pixels, std::uint32_t width, std::uint32_t height,
                std::uint16_t bits, std::uint16_t format, std::uint16_t samples_per_pixel,
                const Layout& layout, const std::function<void(TIFF*)>& extra = {}) {
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, width);
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, height);
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, bits);
  TIFFSetField(tiff, TIFFTAG_SAMPLEFORMAT, format);
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, samples_per_pixel);
  TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC,
               samples_per_pixel == 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, layout.compression);
  if (extra) extra(tiff);
  const std::size_t pixel_bytes = std::size_t{bits} / 8 * samples_per_pixel;
  const auto* bytes = static_cast<const unsigned char*>(pixels);
  if (!layout.tiled) {
    TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, layout.rows_per_strip);
    std::vector<unsigned char> row(width * pixel_bytes);
    for (std::uint32_t y = 0; y < height; ++y) {
      std::copy(bytes + y * row.size(), bytes + (y + 1) * row.size(), row.begin());
      ASSERT_EQ(TIFFWriteScanline(tiff, row.data(), y, 0), 1);
    }
  } else {
    constexpr std::uint32_t kTile = 16;
    TIFFSetField(tiff, TIFFTAG_TILEWIDTH, kTile);
    TIFFSetField(tiff, TIFFTAG_TILELENGTH, kTile);
    std::vector<unsigned char> tile(kTile * kTile * pixel_bytes);
    for (std::uint32_t ty = 0; ty < height; ty += kTile) {
      for (std::uint32_t tx = 0; tx < width; tx += kTile) {
        std::fill(tile.begin(), tile.end(), 0xee);  // padding the reader must not copy
        for (std::uint32_t y = ty; y < std::min(ty + kTile, height); ++y)
          for (std::uint32_t x = tx; x < std::min(tx + kTile, width); ++x)
            std::copy_n(bytes + (std::size_t{y} * width + x) * pixel_bytes, pixel_bytes,
                        tile.begin() + ((y - ty) * kTile + (x - tx)) * pixel_bytes);
        ASSERT_GE(TIFFWriteTile(tiff, tile.data(), tx, ty, 0, 0), 0);
      }
    }
  }
  ASSERT_EQ(TIFFWriteDirectory(tiff), 1);
}

// Writes `depth` pages of `samples` (x fastest, then y, then page).
template <typename T>
void write_stack(const std::string& path, const std::vector<T>& samples, std::uint32_t width,
                 std::uint32_t height, std::uint32_t first_page, std::uint32_t page_count,
                 const Layout& layout, const std::function<void(TIFF*)>& extra = {},
                 const char* mode = "w") {
  TIFF* tiff = TIFFOpen(path.c_str(), mode);
  ASSERT_NE(tiff, nullptr) << path;
  const std::size_t page_samples = std::size_t{width} * height;
  for (std::uint32_t page = first_page; page < first_page + page_count; ++page) {
    write_page(tiff, samples.data() + page * page_samples, width, height, 8 * sizeof(T),
               sample_format<T>(), 1, layout, extra);
  }
  TIFFClose(tiff);
}

template <typename T>
std::vector<T> read_stack(const std::vector<std::string>& inputs, VolumeInfo* info = nullptr) {
  auto source = open_slice_source(inputs, std::nullopt);
  if (info) *info = source->info();
  return test::read_samples<T>(*source);
}

template <typename T>
void expect_round_trip(SampleType type) {
  const std::vector<T> samples = test::phantom_samples<T>(kWidth, kHeight, kDepth);
  for (const Layout& layout : kLayouts) {
    SCOPED_TRACE(std::string(sample_type_name(type)) + ", " + layout.name);
    ScratchDirectory dir;
    write_stack(dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, layout);
    VolumeInfo info;
    EXPECT_EQ(read_stack<T>({dir / "stack.tif"}, &info), samples);
    EXPECT_EQ(info.width, kWidth);
    EXPECT_EQ(info.height, kHeight);
    EXPECT_EQ(info.depth, kDepth);
    EXPECT_EQ(info.type, type);
    for (double spacing : info.spacing) EXPECT_EQ(spacing, 1);
  }
}

TEST(TiffStack, EveryPageTypeStripedAndTiledRoundTrips) {
  expect_round_trip<std::uint8_t>(SampleType::u8);
  expect_round_trip<std::uint16_t>(SampleType::u16);
  expect_round_trip<std::int16_t>(SampleType::i16);
  expect_round_trip<float>(SampleType::f32);
}

// Writes each slice as its own image file with OpenCV, named so that natural order is z order.
template <typename T>
std::vector<std::string> write_slice_files(const ScratchDirectory& dir,
                                           const std::vector<T>& samples, int cv_type,
                                           const std::string& extension) {
  std::vector<std::string> files;
  for (std::uint32_t z = 0; z < kDepth; ++z) {
    cv::Mat image(kHeight, kWidth, cv_type,
                  const_cast<T*>(samples.data() + std::size_t{z} * kWidth * kHeight));
    files.push_back(dir / ("slice" + std::to_string(z) + extension));
    EXPECT_TRUE(cv::imwrite(files.back(), image)) << files.back();
  }
  return files;
}

template <typename T>
void expect_mesh_equals_separate_slices(int cv_type, const std::string& extension) {
  SCOPED_TRACE(extension);
  const std::vector<T> samples = test::phantom_samples<T>(kWidth, kHeight, kDepth);
  const double threshold = test::sample_from_density<T>(0.1);
  ScratchDirectory dir;
  write_stack(dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[2]);
  ImageStackSource slices(write_slice_files(dir, samples, cv_type, extension));
  auto stack = open_slice_source({dir / "stack.tif"}, std::nullopt);
  const test::Mesh from_stack = test::extract(*stack, threshold);
  EXPECT_TRUE(test::meshes_identical(from_stack, test::extract(slices, threshold)));
  EXPECT_GT(from_stack.polygons.size(), 100u);
  EXPECT_TRUE(test::analyse(from_stack).closed_and_consistent());
}

TEST(TiffStack, MeshEqualsTheSameSlicesAsSeparateFiles) {
  expect_mesh_equals_separate_slices<std::uint8_t>(CV_8U, ".png");
  expect_mesh_equals_separate_slices<std::uint16_t>(CV_16U, ".png");
  expect_mesh_equals_separate_slices<std::int16_t>(CV_16S, ".tiff");  // OpenCV's TIFF reader

  // OpenCV's image stacks refuse float slices, so float pages are checked against the raw
  // volume reader on the same samples.
  const std::vector<float> samples = test::phantom_samples<float>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  write_stack(dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[1]);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  std::ofstream(dir / "volume.raw", std::ios::binary)
      .write(reinterpret_cast<const char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
  RawVolumeSource raw_source(dir / "volume.raw", parse_raw_format("37x29x7:f32le"));
  auto stack = open_slice_source({dir / "stack.tif"}, std::nullopt);
  const double threshold = test::sample_from_density<float>(0.1);
  const test::Mesh from_stack = test::extract(*stack, threshold);
  EXPECT_TRUE(test::meshes_identical(from_stack, test::extract(raw_source, threshold)));
  EXPECT_GT(from_stack.polygons.size(), 100u);
}

TEST(TiffStack, SinglePageTiffGivesWhatOpenCvGives) {
  const std::vector<std::uint16_t> samples =
      test::phantom_samples<std::uint16_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  write_stack(dir / "one.tif", samples, kWidth, kHeight, 3, 1, kLayouts[0]);
  ImageStackSource opencv({dir / "one.tif"});
  TiffStackSource libtiff({dir / "one.tif"});
  const std::vector<std::uint16_t> expected(samples.begin() + 3 * kWidth * kHeight,
                                            samples.begin() + 4 * kWidth * kHeight);
  EXPECT_EQ(test::read_samples<std::uint16_t>(libtiff), expected);
  EXPECT_EQ(test::read_samples<std::uint16_t>(opencv), expected);
}

TEST(TiffStack, SeveralFilesAreConcatenatedInNaturalOrder) {
  const std::vector<std::int16_t> samples =
      test::phantom_samples<std::int16_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  fs::create_directories(dir / "parts");
  // part2 sorts before part10 in natural order, not in plain string order.
  write_stack(dir / "parts/part1.tif", samples, kWidth, kHeight, 0, 3, kLayouts[0]);
  write_stack(dir / "parts/part2.tif", samples, kWidth, kHeight, 3, 1, kLayouts[2]);
  write_stack(dir / "parts/part10.tiff", samples, kWidth, kHeight, 4, 3, kLayouts[1]);
  VolumeInfo info;
  EXPECT_EQ(read_stack<std::int16_t>({dir / "parts"}, &info), samples);
  EXPECT_EQ(info.depth, kDepth);
}

TEST(TiffStack, ImageJSpacingIsUsedOtherResolutionsAreNot) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  write_stack(dir / "imagej.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[0], [](TIFF* tiff) {
    TIFFSetField(tiff, TIFFTAG_IMAGEDESCRIPTION,
                 "ImageJ=1.54f\nimages=7\nslices=7\nunit=mm\nspacing=2.5\nloop=false\n");
    TIFFSetField(tiff, TIFFTAG_XRESOLUTION, 2.0f);  // pixels per mm
    TIFFSetField(tiff, TIFFTAG_YRESOLUTION, 4.0f);
    TIFFSetField(tiff, TIFFTAG_RESOLUTIONUNIT, RESUNIT_NONE);
  });
  VolumeInfo info;
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "imagej.tif"}, &info), samples);
  EXPECT_DOUBLE_EQ(info.spacing[0], 0.5);
  EXPECT_DOUBLE_EQ(info.spacing[1], 0.25);
  EXPECT_DOUBLE_EQ(info.spacing[2], 2.5);

  // A scanner's 300 dpi says nothing about voxels.
  write_stack(dir / "dpi.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[0], [](TIFF* tiff) {
    TIFFSetField(tiff, TIFFTAG_XRESOLUTION, 300.0f);
    TIFFSetField(tiff, TIFFTAG_YRESOLUTION, 300.0f);
    TIFFSetField(tiff, TIFFTAG_RESOLUTIONUNIT, RESUNIT_INCH);
  });
  read_stack<std::uint8_t>({dir / "dpi.tif"}, &info);
  for (double spacing : info.spacing) EXPECT_EQ(spacing, 1);
}

// ---------------------------------------------------------------------------------------------
// Refusals

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

void write_file(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

std::vector<unsigned char> filled(std::size_t size, unsigned char value) {
  return std::vector<unsigned char>(size, value);
}

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
  write_file(
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
  write_file(dir / "short.tif",
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
  write_file(
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

TEST(TiffStack, HeadersDeclaringMoreThanTheirDataCanHoldAreRefusedBeforeAnySlice) {
  ScratchDirectory dir;
  const auto refusal = [&](const test::TiffPageBytes& page) {
    write_file(dir / "lying.tif", test::tiff_file_bytes({page}));
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
  write_file(
      dir / "fixed.tif",
      test::tiff_file_bytes(
          {{12, 10, 8, COMPRESSION_ADOBE_DEFLATE, 0, 256, 256, {test::zlib_compressed(tile)}}}));
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "fixed.tif"}), expected);
  // 4096x4096 whatever the image.
  write_file(
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
  write_file(dir / "huge.tif", test::tiff_file_bytes({{12,
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
  write_file(
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
  write_file(dir / "zstd.tif",
             test::tiff_file_bytes(
                 {{0x80000000u, 0x40000000u, 16, COMPRESSION_ZSTD, 0, 0, 0, {filled(64, 1)}}}));
  TiffStackSource source({dir / "zstd.tif"});
  EXPECT_EQ(source.working_bytes(), (std::uint64_t{1} << 62) + 1024);
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
  // The largest stored strip or tile, from libtiff.
  const auto largest_chunk = [](const std::string& path) {
    std::uint64_t largest = 0;
    TIFF* tiff = TIFFOpen(path.c_str(), "r");
    do {
      const std::uint32_t count =
          TIFFIsTiled(tiff) ? TIFFNumberOfTiles(tiff) : TIFFNumberOfStrips(tiff);
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
    std::uint64_t expected = slice + (layout.tiled ? 16 * 16 * 2 : 0);
    const std::uint64_t chunk = largest_chunk(dir / "stack.tif");
    if (layout.compression == COMPRESSION_ADOBE_DEFLATE)
      expected += chunk + ZlibStreamCheck::kWorkingBytes;
    else if (layout.compression != COMPRESSION_NONE)
      expected += (chunk + 1023) / 1024 * 1024;
    EXPECT_EQ(source.working_bytes(), expected);
    EXPECT_EQ(test::read_samples<std::uint16_t>(source), samples);
  }
}

TEST(TiffStack, MultiPageTiffAmongOtherImagesIsRefused) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  write_stack(dir / "a.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[0]);
  ASSERT_TRUE(cv::imwrite(dir / "b.png", cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(3))));
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir.path().string()}, std::nullopt); }),
                  dir / "a.tif: is a TIFF stack of 7 pages among other images");
  // A single-page TIFF among PNG slices is just a slice.
  write_stack(dir / "a.tif", samples, kWidth, kHeight, 0, 1, kLayouts[0]);
  auto source = open_slice_source({dir.path().string()}, std::nullopt);
  EXPECT_EQ(source->info().depth, 2u);
}

TEST(TiffStackCli, ExtractsAStackAndRefusesATruncatedOne) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  write_stack(dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[3]);
  const test::CommandResult ok =
      test::run_mvox("extract stack.tif -t 25 -o stack.ply -q --stats stack.json", dir.path());
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(dir / "stack.ply"));

  fs::copy_file(dir / "stack.tif", dir / "cut.tif");
  fs::resize_file(dir / "cut.tif", fs::file_size(dir / "stack.tif") / 3);
  const std::string before = dir.listing();
  test::expect_one_line_error(test::run_mvox("extract cut.tif -t 25 -o cut.ply", dir.path()),
                              "cut.tif");
  EXPECT_EQ(dir.listing(), before) << "an output or temporary was left behind";
}

}  // namespace
}  // namespace mvox
