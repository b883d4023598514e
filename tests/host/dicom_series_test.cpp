// DICOM series as volumes (src/read/dicom/dicom_volume_plan.h, dicom_input.h), on files written
// here with GDCM: slices ordered by position along an oblique normal (or InstanceNumber), the
// largest of several series or the one --series picks, files that are not DICOM images skipped
// and inconsistent series refused, multi-frame files, and when INPUT counts as DICOM.
#include "dicom_series.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "dicom_writer.h"
#include "read/dicom/dicom_input.h"
#include "read/dicom/dicom_series_source.h"
#include "read/input_format.h"

namespace mvox {
namespace {

namespace fs = std::filesystem;
using test::DicomSliceSpec;
using test::ScratchDirectory;
using test::dicom_series::cross;
using test::dicom_series::dot;
using test::dicom_series::expect_error;
using test::dicom_series::open_series;
using test::dicom_series::pattern;
using test::dicom_series::read_values;
using test::dicom_series::Vec3;
using test::dicom_series::write_series;

std::string text_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// ---------------------------------------------------------------------------------------------
// Order and geometry

TEST(DicomSeries, ShuffledFilesAreOrderedByPositionAlongAnObliqueNormal) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.width = 20;  // odd sizes, and different row and column spacings, to catch axis swaps
  spec.height = 13;
  spec.orientation = test::oblique_orientation(20, -35, 10);
  spec.pixel_spacing = std::array<double, 2>{0.7, 0.4};  // rows 0.7 mm apart, columns 0.4 mm
  const Vec3 origin{-40.5, 12.25, 87};
  // File i holds the slice at position order[i]; InstanceNumbers follow a third order, so
  // neither the names nor the numbers give the right answer.
  const std::vector<int> order = {3, 0, 6, 1, 5, 2, 4};
  const std::vector<int> instance = {5, 2, 7, 1, 4, 6, 3};
  const auto& o = *spec.orientation;
  const Vec3 row{o[0], o[1], o[2]}, column{o[3], o[4], o[5]};
  const Vec3 normal = cross(row, column);
  for (int i = 0; i < 7; ++i) {
    const int k = order[i];
    spec.instance_number = instance[i];
    spec.position = Vec3{origin[0] + k * 2.5 * normal[0], origin[1] + k * 2.5 * normal[1],
                         origin[2] + k * 2.5 * normal[2]};
    spec.stored = pattern(spec.width, spec.height, k);
    test::write_dicom(dir / ("im" + std::to_string(i) + ".dcm"), spec);
  }

  DicomSeriesSource source = open_series(dir.path().string());
  const VolumeInfo& info = source.info();
  EXPECT_EQ(info.width, 20u);
  EXPECT_EQ(info.height, 13u);
  EXPECT_EQ(info.depth, 7u);
  EXPECT_EQ(info.type, SampleType::u16);
  EXPECT_NEAR(info.spacing[0], 0.4, 1e-9);  // x: between columns, PixelSpacing's second value
  EXPECT_NEAR(info.spacing[1], 0.7, 1e-9);  // y: between rows, its first value
  EXPECT_NEAR(info.spacing[2], 2.5, 1e-6);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(info.origin[i], origin[i], 1e-6) << i;
    EXPECT_NEAR(info.axes[0][i], row[i], 1e-8) << i;
    EXPECT_NEAR(info.axes[1][i], column[i], 1e-8) << i;
    EXPECT_NEAR(info.axes[2][i], normal[i], 1e-8) << i;
  }
  for (int z = 0; z < 7; ++z) {
    const DicomSliceRef& slice = source.plan().slices[z];
    const int file = static_cast<int>(std::find(order.begin(), order.end(), z) - order.begin());
    EXPECT_EQ(fs::path(source.plan().headers[slice.header].path).filename(),
              "im" + std::to_string(file) + ".dcm");
    EXPECT_NEAR(slice.position_mm, dot(origin, normal) + 2.5 * z, 1e-6);
  }
  const std::vector<double> values = read_values(source);
  ASSERT_EQ(values.size(), 20u * 13 * 7);
  for (int z = 0; z < 7; ++z) {
    const std::vector<std::int64_t> expected = pattern(20, 13, z);
    for (std::size_t i = 0; i < expected.size(); ++i)
      ASSERT_EQ(values[z * expected.size() + i], expected[i]) << "slice " << z << " sample " << i;
  }
}

TEST(DicomSeries, WithoutPositionsSlicesFollowInstanceNumberAndTheNoteSaysSo) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.spacing_between_slices = 3;
  const std::vector<int> instance = {2, 3, 1};  // file i is slice instance[i] - 1
  for (int i = 0; i < 3; ++i) {
    spec.instance_number = instance[i];
    spec.stored = pattern(spec.width, spec.height, instance[i] - 1);
    test::write_dicom(dir / ("s" + std::to_string(i) + ".dcm"), spec);
  }
  std::vector<std::string> notes;
  DicomSeriesSource source = open_series(dir.path().string(), &notes);
  EXPECT_EQ(source.info().spacing[2], 3);
  const std::vector<double> values = read_values(source);
  for (int z = 0; z < 3; ++z) EXPECT_EQ(values[z * 16 * 12 + 5], pattern(16, 12, z)[5]) << z;
  ASSERT_EQ(notes.size(), 2u);  // the order, and the missing PixelSpacing
  EXPECT_NE(notes[0].find("ordered by InstanceNumber, 3 mm apart (SpacingBetweenSlices)"),
            std::string::npos)
      << notes[0];
  EXPECT_NE(notes[1].find("no PixelSpacing"), std::string::npos) << notes[1];
}

// ---------------------------------------------------------------------------------------------
// Several series

TEST(DicomSeries, TheLargestSeriesIsReadAndSeriesPicksAnother) {
  ScratchDirectory dir;
  DicomSliceSpec big, small;
  big.series_uid = "1.2.826.0.1.3680043.10.543.7";
  big.series_description = "AX T1";
  small.series_uid = "1.2.826.0.1.3680043.10.543.9";
  small.width = 8;
  write_series(dir.path().string(), "a", big, 5, {0, 0, 0}, 1.5);
  write_series(dir.path().string(), "b", small, 3, {0, 0, 0}, 4);

  std::vector<std::string> notes;
  DicomSeriesSource largest = open_series(dir.path().string(), &notes);
  EXPECT_EQ(largest.series_uid(), big.series_uid);
  EXPECT_EQ(largest.info().depth, 5u);
  ASSERT_GE(notes.size(), 1u);
  EXPECT_NE(notes[0].find("2 DICOM series; reading the largest, " + big.series_uid +
                          " 'AX T1' (5 slices); also " + small.series_uid +
                          " (3 slices); choose one with --series UID"),
            std::string::npos)
      << notes[0];

  notes.clear();
  DicomSeriesSource chosen = open_series(dir.path().string(), &notes, small.series_uid);
  EXPECT_EQ(chosen.series_uid(), small.series_uid);
  EXPECT_EQ(chosen.info().depth, 3u);
  EXPECT_EQ(chosen.info().width, 8u);
  EXPECT_EQ(chosen.info().spacing[2], 4);
  for (const std::string& note : notes) EXPECT_EQ(note.find("DICOM series"), std::string::npos);

  expect_error([&] { open_series(dir.path().string(), nullptr, "1.2.3.4"); }, "--series",
               "no series 1.2.3.4 in " + dir.path().string() + "; it holds " + big.series_uid +
                   " 'AX T1' (5 slices), " + small.series_uid + " (3 slices)");
}

// ---------------------------------------------------------------------------------------------
// What is skipped, what is refused

TEST(DicomSeries, FilesThatAreNotDicomImagesAreSkipped) {
  ScratchDirectory dir;
  write_series(dir.path().string(), "slice", DicomSliceSpec{}, 4, {0, 0, 0}, 1);
  text_file(dir / "INFO.txt", "A series of four slices.\n");
  text_file(dir / "preview.png", std::string("\x89PNG\r\n\x1a\n", 8) + std::string(100, 'x'));
  text_file(dir / "SHA256SUMS", "0000  slice0.dcm\n");
  DicomSliceSpec directory;  // a DICOMDIR: DICOM, but no image
  directory.with_image = false;
  directory.sop_class_uid = "1.2.840.10008.1.3.10";
  test::write_dicom(dir / "DICOMDIR", directory);

  DicomSeriesSource source = open_series(dir.path().string());
  EXPECT_EQ(source.info().depth, 4u);
  EXPECT_EQ(read_values(source).size(), 4u * 16 * 12);
  EXPECT_TRUE(is_dicom_input({dir.path().string()}));

  ScratchDirectory nothing;
  text_file(nothing / "INFO.txt", "no images\n");
  expect_error([&] { open_series(nothing.path().string()); }, nothing.path().string(),
               "no DICOM image among 1 file");
}

TEST(DicomSeries, InconsistentSeriesAreRefusedNamingTheFile) {
  struct Case {
    const char* name;
    std::function<void(DicomSliceSpec&, int)> change;  // applied to the spec of file `index`
    int file;                                          // the file the error names
    const char* words;
  };
  const Case cases[] = {
      {"same position",
       [](DicomSliceSpec& s, int i) {
         if (i == 2) s.position = Vec3{0, 0, 1};
       },
       2, "lies at the same position along the slice normal (1 mm) as"},
      {"missing slice",
       [](DicomSliceSpec& s, int i) {
         if (i == 3) s.position = Vec3{0, 0, 4};
       },
       3, "lies 2 mm from the previous slice"},
      {"size",
       [](DicomSliceSpec& s, int i) {
         if (i == 1) s.width = 15;
       },
       1, "image is 15x12, expected 16x12 like the first slice"},
      {"pixel type",
       [](DicomSliceSpec& s, int i) {
         if (i == 2) s.is_signed = true;
       },
       2, "pixels are 16-bit signed, expected 16-bit unsigned"},
      {"orientation",
       [](DicomSliceSpec& s, int i) {
         if (i == 3) s.orientation = test::oblique_orientation(0, 0, 5);
       },
       3, "orientation"},
      {"colour",
       [](DicomSliceSpec& s, int i) {
         if (i == 1) s.photometric = "RGB", s.samples_per_pixel = 3, s.bits_allocated = 8;
       },
       1, "colour image (PhotometricInterpretation RGB, 3 samples per pixel)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ScratchDirectory dir;
    for (int i = 0; i < 4; ++i) {
      DicomSliceSpec spec;
      spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
      spec.position = Vec3{0, 0, double(i)};
      spec.bits_stored = spec.bits_allocated = 16;
      c.change(spec, i);
      if (spec.bits_allocated == 8) spec.bits_stored = 8;
      spec.stored = pattern(spec.width, spec.height, i);
      test::write_dicom(dir / ("f" + std::to_string(i) + ".dcm"), spec);
    }
    expect_error([&] { open_series(dir.path().string()); },
                 dir / ("f" + std::to_string(c.file) + ".dcm"), c.words);
  }
}

// ---------------------------------------------------------------------------------------------
// Multi-frame files and input detection

TEST(DicomSeries, AMultiFrameFileGivesItsFramesAsSlices) {
  ScratchDirectory dir, rle;
  DicomSliceSpec spec;
  spec.width = 24;
  spec.height = 20;
  spec.frames = 4;
  spec.position = Vec3{5, 6, 7};
  spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
  spec.spacing_between_slices = 2.5;
  for (int k = 0; k < 4; ++k) {
    const auto frame = pattern(24, 20, k);
    spec.stored.insert(spec.stored.end(), frame.begin(), frame.end());
  }
  test::write_dicom(dir / "frames.dcm", spec);
  ASSERT_TRUE(test::recode(dir / "frames.dcm", rle / "frames.dcm", test::kRleLosslessUid));

  std::vector<std::string> notes;
  DicomSeriesSource source = open_series(dir.path().string(), &notes);
  EXPECT_EQ(source.info().depth, 4u);
  EXPECT_EQ(source.info().spacing[2], 2.5);
  EXPECT_EQ(source.info().origin[2], 7);
  const std::vector<double> values = read_values(source);
  ASSERT_EQ(values.size(), spec.stored.size());
  for (std::size_t i = 0; i < values.size(); ++i) ASSERT_EQ(values[i], spec.stored[i]) << i;
  ASSERT_GE(notes.size(), 1u);
  EXPECT_NE(notes[0].find("frames of"), std::string::npos) << notes[0];

  DicomSeriesSource compressed = open_series(rle.path().string());
  EXPECT_EQ(read_values(compressed), values);

  // A multi-frame file among single-frame ones is refused.
  DicomSliceSpec single;
  single.width = 24;
  single.height = 20;
  test::write_dicom(dir / "single.dcm", single);
  expect_error([&] { open_series(dir.path().string()); }, dir / "frames.dcm",
               "is a multi-frame file (4 frames) in a series of several files");
}

TEST(DicomInput, DetectedByPreambleOrNameOtherwiseOnlyWithDicom) {
  ScratchDirectory named, unnamed, bare, images;
  write_series(named.path().string(), "s", DicomSliceSpec{}, 2, {0, 0, 0}, 1);
  DicomSliceSpec spec;
  spec.stored = pattern(16, 12, 0);
  test::write_dicom(unnamed / "IM0001", spec);  // preamble, no extension
  spec.with_meta = false;
  spec.transfer_syntax_uid = test::kImplicitLittleEndianUid;
  test::write_dicom(bare / "IM0001", spec);  // an old file: neither preamble nor name
  text_file(images / "a.png", "not really a PNG");

  EXPECT_TRUE(is_dicom_input({named.path().string()}));
  EXPECT_TRUE(is_dicom_input({unnamed.path().string()}));
  EXPECT_TRUE(is_dicom_input({unnamed / "IM0001"}));
  EXPECT_FALSE(is_dicom_input({bare.path().string()}));
  EXPECT_FALSE(is_dicom_input({images.path().string()}));
  EXPECT_FALSE(is_dicom_input({"/no/such/directory"}));

  DicomChoice force;
  force.force = true;
  auto forced = open_slice_source({bare.path().string()}, std::nullopt, force);
  EXPECT_EQ(forced->info().width, 16u);
  EXPECT_EQ(read_values(*forced), read_values(*open_slice_source({unnamed / "IM0001"}, {})));

  DicomChoice series;
  series.series_uid = "1.2.3";
  expect_error([&] { open_slice_source({images.path().string()}, std::nullopt, series); },
               "--series", "applies to DICOM input only");
}

}  // namespace
}  // namespace mvox
