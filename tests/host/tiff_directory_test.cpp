// mvox's own reading of TIFF directories (src/read/tiff/tiff_directory.h), against libtiff's on
// files libtiff writes (classic and BigTIFF, both byte orders, strips and tiles, both fill
// orders), and its refusals of directories that cannot be read, naming file and page.
#include "read/tiff/tiff_directory.h"

#include <gtest/gtest.h>
#include <tiffio.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "file_io.h"
#include "read/tiff/tiff_stack_source.h"
#include "tiff_bytes.h"
#include "tiff_stack_files.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::ScratchDirectory;
using test::tiff_stack_files::kDepth;
using test::tiff_stack_files::kHeight;
using test::tiff_stack_files::kLayouts;
using test::tiff_stack_files::kWidth;
using test::tiff_stack_files::Layout;
using test::tiff_stack_files::read_stack;
using test::tiff_stack_files::write_stack;

// Every page's directory as mvox reads it equals libtiff's reading of it.
void expect_directories_as_libtiff_reads_them(const std::string& path) {
  TiffDirectoryReader reader(path);
  TIFF* tiff = TIFFOpen(path.c_str(), "r");
  ASSERT_NE(tiff, nullptr);
  TiffDirectory page;
  int pages = 0;
  do {
    SCOPED_TRACE("page " + std::to_string(pages + 1));
    ASSERT_TRUE(reader.next(&page));
    std::uint32_t width = 0, height = 0;
    std::uint16_t bits = 0, compression = 0, fill_order = 0, sample_format = 0;
    TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &width);
    TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &height);
    TIFFGetFieldDefaulted(tiff, TIFFTAG_BITSPERSAMPLE, &bits);
    TIFFGetFieldDefaulted(tiff, TIFFTAG_COMPRESSION, &compression);
    TIFFGetFieldDefaulted(tiff, TIFFTAG_FILLORDER, &fill_order);
    TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLEFORMAT, &sample_format);
    EXPECT_EQ(page.width, width);
    EXPECT_EQ(page.height, height);
    EXPECT_EQ(page.bits_per_sample, bits);
    EXPECT_EQ(page.compression, compression);
    EXPECT_EQ(page.fill_order, fill_order);
    EXPECT_EQ(page.sample_format, sample_format);
    EXPECT_EQ(reader.byte_swapped(), TIFFIsByteSwapped(tiff) != 0);
    EXPECT_EQ(page.tiled, TIFFIsTiled(tiff) != 0);
    const std::uint32_t chunks = page.tiled ? TIFFNumberOfTiles(tiff) : TIFFNumberOfStrips(tiff);
    ASSERT_EQ(page.chunk_offsets.size(), chunks);
    for (std::uint32_t i = 0; i < chunks; ++i) {
      EXPECT_EQ(page.chunk_offsets[i], TIFFGetStrileOffset(tiff, i)) << i;
      EXPECT_EQ(page.chunk_bytes[i], TIFFGetStrileByteCount(tiff, i)) << i;
    }
    ++pages;
  } while (TIFFReadDirectory(tiff));
  TIFFClose(tiff);
  EXPECT_FALSE(reader.next(&page)) << "mvox reads more pages than libtiff";
}

template <typename T>
void expect_read_as_written(const std::string& path, const Layout& layout, const char* mode,
                            std::uint16_t fill_order) {
  const std::vector<T> samples = test::phantom_samples<T>(kWidth, kHeight, kDepth);
  write_stack(
      path, samples, kWidth, kHeight, 0, kDepth, layout,
      [&](TIFF* tiff) { TIFFSetField(tiff, TIFFTAG_FILLORDER, fill_order); }, mode);
  expect_directories_as_libtiff_reads_them(path);
  EXPECT_EQ(read_stack<T>({path}), samples);
}

TEST(TiffDirectory, ClassicAndBigTiffInBothByteOrdersReadAsLibtiffReadsThem) {
  ScratchDirectory dir;
  // l, b: little- and big-endian; 8: BigTIFF.
  for (const char* mode : {"wl", "wb", "w8l", "w8b"}) {
    for (const Layout& layout : kLayouts) {
      for (const std::uint16_t fill_order : {FILLORDER_MSB2LSB, FILLORDER_LSB2MSB}) {
        SCOPED_TRACE(std::string(mode) + ", " + layout.name + ", fill order " +
                     std::to_string(fill_order));
        const std::string path = dir / "stack.tif";
        expect_read_as_written<std::uint8_t>(path, layout, mode, fill_order);
        expect_read_as_written<std::uint16_t>(path, layout, mode, fill_order);
        expect_read_as_written<std::int16_t>(path, layout, mode, fill_order);
        expect_read_as_written<float>(path, layout, mode, fill_order);
      }
    }
  }
}

TEST(TiffDirectory, UncompressedPagesWithoutByteCountsHoldTheirSamples) {
  // A writer may leave StripByteCounts out of an uncompressed page, as libtiff reads it.
  ScratchDirectory dir;
  std::vector<unsigned char> samples(12 * 10);
  for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<unsigned char>(i);
  std::vector<unsigned char> bytes = test::tiff_file_bytes(
      {{12,
        10,
        8,
        COMPRESSION_NONE,
        5,
        0,
        0,
        {{samples.begin(), samples.begin() + 60}, {samples.begin() + 60, samples.end()}}}});
  test::rename_tiff_tag(bytes, 0, TIFFTAG_STRIPBYTECOUNTS, 65000);
  test::write_bytes(dir / "no_counts.tif", bytes);
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "no_counts.tif"}),
            std::vector<std::uint8_t>(samples.begin(), samples.end()));
}

TEST(TiffDirectory, DirectoriesLongerThanTheFirstReadAreReadWhole) {
  // Page 1's directory copied to the end of the file after 300 entries of unknown tags (3.6 KB,
  // several times the first read of a directory): what mvox needs is in the last entries.
  ScratchDirectory dir;
  std::vector<unsigned char> samples(12 * 10);
  for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<unsigned char>(i);
  std::vector<unsigned char> bytes =
      test::tiff_file_bytes({{12, 10, 8, COMPRESSION_NONE, 0, 0, 0, {samples}}});
  const std::uint32_t old_directory = test::tiff_directory_offset(bytes, 0);
  const std::uint32_t old_entries = bytes[old_directory] | bytes[old_directory + 1] << 8;
  const std::uint32_t directory = static_cast<std::uint32_t>(bytes.size());
  bytes.resize(bytes.size() + 2 + 12 * (300 + old_entries) + 4);
  test::put_tiff_u16(bytes, directory, 300 + old_entries);
  for (std::uint32_t i = 0; i < 300; ++i) {
    const std::size_t entry = directory + 2 + 12 * i;
    test::put_tiff_u16(bytes, entry, 60000 + i);  // a private tag
    test::put_tiff_u16(bytes, entry + 2, 3);      // SHORT
    test::put_tiff_u32(bytes, entry + 4, 1);
  }
  std::copy_n(bytes.begin() + old_directory + 2, 12 * old_entries,
              bytes.begin() + directory + 2 + 12 * 300);
  test::put_tiff_u32(bytes, 4, directory);
  test::write_bytes(dir / "long.tif", bytes);
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "long.tif"}),
            std::vector<std::uint8_t>(samples.begin(), samples.end()));
}

TEST(TiffDirectory, ADamagedDescriptionOrResolutionReadsAsAbsent) {
  // An ImageDescription whose text lies past the end of the file, and an XResolution of a
  // negative integer: libtiff reads the page without them, and so does mvox.
  ScratchDirectory dir;
  const std::vector<unsigned char> samples(12 * 10, 9);
  std::vector<unsigned char> bytes =
      test::tiff_file_bytes({{12, 10, 8, COMPRESSION_NONE, 0, 0, 0, {samples}}});
  const std::size_t photometric = test::tiff_entry_offset(bytes, 0, TIFFTAG_PHOTOMETRIC);
  test::put_tiff_u16(bytes, photometric, TIFFTAG_IMAGEDESCRIPTION);
  test::put_tiff_u16(bytes, photometric + 2, 2);  // ASCII
  test::put_tiff_u32(bytes, photometric + 4, 100);
  test::put_tiff_u32(bytes, photometric + 8, 0xfffffff0u);
  const std::size_t samples_per_pixel = test::tiff_entry_offset(bytes, 0, TIFFTAG_SAMPLESPERPIXEL);
  test::put_tiff_u16(bytes, samples_per_pixel, TIFFTAG_XRESOLUTION);
  test::put_tiff_u16(bytes, samples_per_pixel + 2, 9);  // SLONG
  test::put_tiff_u32(bytes, samples_per_pixel + 8, 0xfffffff8u);
  test::write_bytes(dir / "damaged.tif", bytes);
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "damaged.tif"}),
            std::vector<std::uint8_t>(samples.begin(), samples.end()));
}

TEST(TiffDirectory, ATagsLaterEntriesAreIgnoredAsLibtiffIgnoresThem) {
  // A deflate page whose PhotometricInterpretation entry is made a second Compression entry,
  // saying "uncompressed": the first one holds.
  ScratchDirectory dir;
  const std::vector<unsigned char> samples(12 * 10, 77);
  std::vector<unsigned char> bytes = test::tiff_file_bytes(
      {{12, 10, 8, COMPRESSION_ADOBE_DEFLATE, 0, 0, 0, {test::zlib_compressed(samples)}}});
  const std::size_t photometric = test::tiff_entry_offset(bytes, 0, TIFFTAG_PHOTOMETRIC);
  test::put_tiff_u16(bytes, photometric, TIFFTAG_COMPRESSION);
  test::put_tiff_u16(bytes, photometric + 8, COMPRESSION_NONE);
  test::write_bytes(dir / "twice.tif", bytes);
  EXPECT_EQ(read_stack<std::uint8_t>({dir / "twice.tif"}),
            std::vector<std::uint8_t>(samples.begin(), samples.end()));
}

std::string refusal(const std::vector<unsigned char>& bytes) {
  ScratchDirectory dir;
  test::write_bytes(dir / "bad.tif", bytes);
  const std::string message = test::error_of([&] { TiffStackSource source({dir / "bad.tif"}); });
  const std::string prefix = dir / "bad.tif" + ": ";
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
  return message.substr(std::min(message.size(), prefix.size()));
}

TEST(TiffDirectory, BrokenHeadersAndDirectoriesAreRefusedNamingThePage) {
  const test::TiffPageBytes page{
      8,
      6,
      8,
      COMPRESSION_NONE,
      2,
      0,
      0,
      {std::vector<unsigned char>(16, 1), std::vector<unsigned char>(16, 2),
       std::vector<unsigned char>(16, 3)}};
  const std::vector<unsigned char> good = test::tiff_file_bytes({page, page});
  {
    ScratchDirectory dir;  // the unbroken file reads
    test::write_bytes(dir / "good.tif", good);
    EXPECT_EQ(read_stack<std::uint8_t>({dir / "good.tif"}).size(), 8u * 6 * 2);
  }

  EXPECT_EQ(refusal({'P', 'K', 3, 4, 0, 0, 0, 0, 0}),
            "cannot read as TIFF: it does not start with II or MM (not a TIFF file)");
  EXPECT_EQ(refusal({'I', 'I', 42, 0}),
            "cannot read as TIFF: the file is 4 bytes, shorter than a TIFF header");
  std::vector<unsigned char> bytes = good;
  bytes[2] = 44;
  EXPECT_EQ(refusal(bytes),
            "cannot read as TIFF: its version is 44, not 42 (TIFF) or 43 (BigTIFF)");
  bytes = good;
  test::put_tiff_u32(bytes, 4, 0);
  EXPECT_EQ(refusal(bytes), "cannot read as TIFF: it has no pages");
  bytes = good;
  test::put_tiff_u32(bytes, 4, static_cast<std::uint32_t>(good.size() + 100));
  EXPECT_EQ(refusal(bytes), "cannot read the directory of page 1: it would start at byte " +
                                std::to_string(good.size() + 100) + ", but the file is " +
                                std::to_string(good.size()) + " bytes (truncated)");

  // Page 2's link to a next directory leads back to page 1.
  bytes = good;
  const std::uint32_t first = test::tiff_directory_offset(bytes, 0);
  test::put_tiff_u32(bytes, test::tiff_next_link(bytes, 1), first);
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 3: it is an earlier page's (the directories loop)");
  // Five pages, the fifth leading back to the third: found when the third comes round again.
  bytes = test::tiff_file_bytes({page, page, page, page, page});
  test::put_tiff_u32(bytes, test::tiff_next_link(bytes, 4), test::tiff_directory_offset(bytes, 2));
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 6: it is an earlier page's (the directories loop)");
  // A directory leading to itself.
  bytes = good;
  test::put_tiff_u32(bytes, test::tiff_next_link(bytes, 1), test::tiff_directory_offset(bytes, 1));
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 4: it is an earlier page's (the directories loop)");

  bytes = good;
  test::put_tiff_u16(bytes, test::tiff_directory_offset(bytes, 1), 5000);
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 2: it claims 5000 entries, more than 4096 (not a "
            "directory)");
  bytes = good;
  bytes.resize(test::tiff_directory_offset(bytes, 1) + 20);
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 2: its 9 entries run past the end of the file "
            "(truncated)");

  bytes = good;
  test::rename_tiff_tag(bytes, 1, TIFFTAG_STRIPOFFSETS, 65000);
  EXPECT_EQ(refusal(bytes), "cannot read the directory of page 2: it has no StripOffsets");
  // One row a strip: the page has 6 strips, its directory places 3.
  bytes = good;
  test::put_tiff_u32(bytes, test::tiff_entry_offset(bytes, 0, TIFFTAG_ROWSPERSTRIP) + 8, 1);
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 1: its StripOffsets hold 3 values, but the page "
            "has 6 strips");
  bytes = good;
  test::put_tiff_u32(bytes, test::tiff_entry_offset(bytes, 0, TIFFTAG_STRIPBYTECOUNTS) + 8,
                     0xfffffff0u);
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 1: the values of its StripByteCounts lie beyond "
            "the end of the file (truncated)");
  bytes = good;
  test::put_tiff_u16(bytes, test::tiff_entry_offset(bytes, 0, TIFFTAG_IMAGEWIDTH) + 2, 2);
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 1: its ImageWidth has field type 2, not an "
            "integer type");
  // A signed type holding a negative width.
  bytes = good;
  const std::size_t width = test::tiff_entry_offset(bytes, 0, TIFFTAG_IMAGEWIDTH);
  test::put_tiff_u16(bytes, width + 2, 9);  // SLONG
  test::put_tiff_u32(bytes, width + 8, 0xfffffff8u);
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 1: its ImageWidth holds a negative value");

  // 1x1 tiles on a 65536x65537 image: more tiles than 32-bit tile numbers (libtiff's too) reach.
  bytes = test::tiff_file_bytes(
      {{65536, 65537, 8, COMPRESSION_NONE, 0, 1, 1, {std::vector<unsigned char>(1, 1)}}});
  EXPECT_EQ(refusal(bytes),
            "cannot read the directory of page 1: it would have 4295032832 tiles, more than "
            "2^32-1");

  // Compressed data need their byte counts.
  test::TiffPageBytes deflate = page;
  deflate.compression = COMPRESSION_ADOBE_DEFLATE;
  for (auto& chunk : deflate.chunks) chunk = test::zlib_compressed(chunk);
  bytes = test::tiff_file_bytes({deflate});
  test::rename_tiff_tag(bytes, 0, TIFFTAG_STRIPBYTECOUNTS, 65000);
  EXPECT_EQ(refusal(bytes), "cannot read the directory of page 1: it has no StripByteCounts");
}

TEST(TiffDirectory, CodecsOfNarrowSamplesAreRefusedBeforeTheSliceIsAllocated) {
  // libtiff refuses to decode CCITT data as 16-bit samples only once asked to decode a strip,
  // which comes after the slice buffer: 65535x4608 here, 576 MiB for a 100-byte file.
  const test::TiffPageBytes page{65535, 4608, 16, COMPRESSION_CCITTRLE,
                                 0,     0,    0,  {std::vector<unsigned char>(100, 1)}};
  EXPECT_EQ(refusal(test::tiff_file_bytes({page})),
            "page 1 uses compression 2 (CCITT, bilevel), which holds samples of 1 to 4 bits, not "
            "the 16 bits it declares");
}

TEST(TiffDirectory, PageCountIsTheNumberOfDirectories) {
  ScratchDirectory dir;
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  write_stack(dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[2], {}, "w8b");
  EXPECT_EQ(tiff_page_count(dir / "stack.tif"), kDepth);
}

}  // namespace
}  // namespace mvox
