// TIFF stacks (src/read/tiff/tiff_stack_source.h) on multi-page files written here with libtiff,
// striped and tiled, compressed or not, for every page type: the samples are the phantom's, the
// mesh the one from the same slices as separate image files (read by OpenCV) or a raw volume;
// several files are concatenated in natural order, ImageJ's spacing is used, and a multi-page
// file among other images is refused.
#include <tiffio.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "gtest/gtest.h"
#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "read/image_stack/image_stack_source.h"
#include "read/input_format.h"
#include "read/raw/raw_volume_source.h"
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
using test::tiff_stack_files::Layout;
using test::tiff_stack_files::read_stack;
using test::tiff_stack_files::write_stack;

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

TEST(TiffStack, EveryRangeReadsItsSlicesOfTheWholeStack) {
  // Three files of three layouts, one decoded by libtiff (LZW), the last one of 40 pages (a
  // range starts from the directory of page 0, 16 or 32 of a file): ranges start at a file's
  // first page, inside a file and in the last one, and end anywhere, as slab workers ask.
  const std::uint32_t depth = 2 * kDepth + 40;
  const std::vector<std::uint16_t> samples =
      test::phantom_samples<std::uint16_t>(kWidth, kHeight, depth);
  ScratchDirectory dir;
  fs::create_directories(dir / "parts");
  write_stack(dir / "parts/a.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[0]);
  write_stack(dir / "parts/b.tif", samples, kWidth, kHeight, kDepth, kDepth, kLayouts[3]);
  write_stack(dir / "parts/c.tif", samples, kWidth, kHeight, 2 * kDepth, 40, kLayouts[1]);
  const std::vector<std::string> files = {dir / "parts/a.tif", dir / "parts/b.tif",
                                          dir / "parts/c.tif"};
  const TiffStackSource whole(files);
  ASSERT_TRUE(whole.range_readable());
  const std::size_t slice = std::size_t{kWidth} * kHeight;
  const std::uint32_t c = 2 * kDepth;  // the first page of c.tif
  const std::vector<std::pair<std::uint32_t, std::uint32_t>> ranges = {
      {0, depth},     {0, 3},           {3, 11},          {kDepth, kDepth + 1}, {kDepth + 2, c + 4},
      {c + 1, depth}, {c + 15, c + 17}, {c + 16, c + 20}, {c + 31, depth},      {c + 39, depth}};
  for (const auto& [first, end] : ranges) {
    SCOPED_TRACE(std::to_string(first) + " to " + std::to_string(end));
    std::unique_ptr<SliceSource> range = whole.open_range(first, end);
    EXPECT_EQ(range->info().depth, depth);
    const std::vector<std::uint16_t> expected(samples.begin() + first * slice,
                                              samples.begin() + end * slice);
    std::vector<std::uint16_t> read;
    SliceView view;
    while (range->next_slice(&view)) {
      const auto* at = static_cast<const std::uint16_t*>(view.samples);
      read.insert(read.end(), at, at + slice);  // rows packed: row_stride_bytes is the row's
    }
    EXPECT_EQ(read, expected);
  }
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

}  // namespace
}  // namespace mvox
