// DICOM series as volumes (src/dicom_*.h): files written here with GDCM, independently of
// mvox's reader, with known geometry and values; then the real files in ../shared/datasets
// (skipped, with the reason, when absent).
#include <gdcmAttribute.h>
#include <gdcmReader.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

#include "command_runner.h"
#include "dicom_writer.h"
#include "error.h"
#include "mesh_capture.h"
#include "mesh_topology.h"
#include "ply_mesh.h"
#include "read/dicom/dicom_input.h"
#include "read/dicom/dicom_series_source.h"
#include "read/dicom/dicom_values.h"
#include "read/input_format.h"
#include "read/ply/ply_reader.h"
#include "shapes.h"

namespace mvox {
namespace {

namespace fs = std::filesystem;
using test::DicomSliceSpec;
using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;
using Vec3 = std::array<double, 3>;

// ---------------------------------------------------------------------------------------------
// Helpers

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

double sample_at(const SliceView& slice, std::uint32_t x, std::uint32_t y) {
  const char* at = static_cast<const char*>(slice.samples) + y * slice.row_stride_bytes;
  switch (slice.type) {
    case SampleType::u8: return static_cast<unsigned char>(at[x]);
    case SampleType::u16: {
      std::uint16_t v;
      std::memcpy(&v, at + 2 * x, 2);
      return v;
    }
    case SampleType::i16: {
      std::int16_t v;
      std::memcpy(&v, at + 2 * x, 2);
      return v;
    }
    case SampleType::f32: {
      float v;
      std::memcpy(&v, at + 4 * x, 4);
      return v;
    }
  }
  return std::nan("");
}

// Every sample of every slice, x fastest, then y, then z, as the engine would see it.
std::vector<double> read_values(SliceSource& source) {
  std::vector<double> values;
  SliceView slice;
  while (source.next_slice(&slice)) {
    EXPECT_EQ(slice.width, source.info().width);
    EXPECT_EQ(slice.type, source.info().type);
    for (std::uint32_t y = 0; y < slice.height; ++y)
      for (std::uint32_t x = 0; x < slice.width; ++x) values.push_back(sample_at(slice, x, y));
  }
  return values;
}

DicomSeriesSource open_series(const std::string& directory,
                              std::vector<std::string>* notes = nullptr,
                              const std::string& series_uid = "") {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(directory))
    files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  DicomOptions options;
  options.label = directory;
  options.series_uid = series_uid;
  if (notes) options.note = [notes](const std::string& line) { notes->push_back(line); };
  return DicomSeriesSource(files, options);
}

// Runs `action`, which must throw mvox::Error about `subject` whose problem mentions `words`.
void expect_error(const std::function<void()>& action, const std::string& subject,
                  const std::string& words) {
  try {
    action();
    ADD_FAILURE() << "no error; expected one about " << subject << " (" << words << ")";
  } catch (const Error& e) {
    EXPECT_EQ(e.subject(), subject) << e.what();
    EXPECT_NE(e.problem().find(words), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

// A slice's stored values: a pattern that differs in every slice, row and column, so that an
// axis swap, a flip or a wrong slice order shows.
std::vector<std::int64_t> pattern(std::uint32_t width, std::uint32_t height, std::int64_t slice,
                                  std::int64_t base = 0) {
  std::vector<std::int64_t> values;
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) values.push_back(base + 300 * slice + 17 * y + x);
  return values;
}

// `count` slices stacked along the normal of `spec.orientation` (axial without one), `gap` mm
// apart from `origin`, stored values pattern(k) for the slice at position k. Files are named
// "<prefix><i>.dcm" with i = position_of_file order: file i holds the slice at position
// order[i] (identity when empty).
void write_series(const std::string& directory, const std::string& prefix, DicomSliceSpec spec,
                  int count, const Vec3& origin, double gap, std::vector<int> order = {}) {
  const auto o = spec.orientation.value_or(std::array<double, 6>{1, 0, 0, 0, 1, 0});
  const Vec3 normal = cross({o[0], o[1], o[2]}, {o[3], o[4], o[5]});
  if (order.empty())
    for (int k = 0; k < count; ++k) order.push_back(k);
  for (int i = 0; i < count; ++i) {
    const int k = order[i];
    spec.position = Vec3{origin[0] + k * gap * normal[0], origin[1] + k * gap * normal[1],
                         origin[2] + k * gap * normal[2]};
    spec.stored = pattern(spec.width, spec.height, k);
    test::write_dicom(directory + "/" + prefix + std::to_string(i) + ".dcm", spec);
  }
}

std::string text_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

void truncate_copy(const std::string& from, const std::string& to, std::uintmax_t bytes) {
  std::ifstream in(from, std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(to, std::ios::binary | std::ios::trunc) << data.substr(0, bytes);
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
// Values

TEST(DicomValues, SampleTypeIsTheSmallestThatHoldsEveryRescaledValueExactly) {
  auto type = [](std::uint16_t bits_stored, bool is_signed, double slope, double intercept) {
    return exact_sample_type({{16, bits_stored, is_signed, slope, intercept}});
  };
  EXPECT_EQ(type(8, false, 1, 0), SampleType::u8);
  EXPECT_EQ(type(12, false, 1, 0), SampleType::u16);  // MR
  EXPECT_EQ(type(16, false, 1, 0), SampleType::u16);
  EXPECT_EQ(type(12, false, 1, -1024), SampleType::i16);  // CT in HU: -1024 .. 3071
  EXPECT_EQ(type(12, false, 2, -1024), SampleType::i16);  // -1024 .. 7166
  EXPECT_EQ(type(16, true, 1, 0), SampleType::i16);
  EXPECT_EQ(type(16, true, 1, -1024), SampleType::f32);   // -33792 .. 31743
  EXPECT_EQ(type(16, false, 1, -1024), SampleType::f32);  // -1024 .. 64511
  EXPECT_EQ(type(12, false, 0.5, 0), SampleType::f32);
  EXPECT_EQ(type(12, false, 1, 0.5), SampleType::f32);
  // Slices of one series may rescale differently: the type holds them all.
  EXPECT_EQ(exact_sample_type({{16, 12, false, 1, 0}, {16, 12, false, 1, -1000}}), SampleType::i16);
  EXPECT_EQ(exact_sample_type({{8, 8, false, 1, 0}, {8, 8, false, 1, 1}}), SampleType::u16);
}

TEST(DicomValues, RescaleUsesOnlyTheStoredBitsAndSignExtendsThem) {
  // 12 stored bits in 16: the top four bits hold junk (an overlay in old files).
  const std::uint16_t unsigned_samples[] = {0x0000, 0x0FFF, 0xF005, 0x1234};
  std::int16_t out[4];
  rescale_samples(unsigned_samples, 4, {16, 12, false, 2, -1024}, SampleType::i16, out);
  EXPECT_EQ(out[0], -1024);
  EXPECT_EQ(out[1], 2 * 4095 - 1024);
  EXPECT_EQ(out[2], 2 * 5 - 1024);
  EXPECT_EQ(out[3], 2 * 0x234 - 1024);
  const std::uint16_t signed_samples[] = {0x0800, 0x07FF, 0xFFFF, 0x0FFF};
  rescale_samples(signed_samples, 4, {16, 12, true, 1, 0}, SampleType::i16, out);
  EXPECT_EQ(out[0], -2048);
  EXPECT_EQ(out[1], 2047);
  EXPECT_EQ(out[2], -1);
  EXPECT_EQ(out[3], -1);
  float f[2];
  const std::uint8_t bytes[] = {0, 255};
  rescale_samples(bytes, 2, {8, 8, false, 0.5, 0.25}, SampleType::f32, f);
  EXPECT_EQ(f[0], 0.25f);
  EXPECT_EQ(f[1], 127.75f);
}

TEST(DicomSeries, RescaleSlopeAndInterceptGiveModalityValues) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.bits_stored = 12;
  spec.slope = 2;
  spec.intercept = -1024;
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  for (int k = 0; k < 3; ++k) {
    spec.position = Vec3{0, 0, double(k)};
    spec.stored = pattern(16, 12, k);
    spec.stored[0] = 0;  // the extremes of 12 bits
    spec.stored[1] = 4095;
    test::write_dicom(dir / ("ct" + std::to_string(k) + ".dcm"), spec);
  }
  DicomSeriesSource source = open_series(dir.path().string());
  EXPECT_EQ(source.info().type, SampleType::i16);
  const std::vector<double> values = read_values(source);
  for (int k = 0; k < 3; ++k) {
    std::vector<std::int64_t> stored = pattern(16, 12, k);
    stored[0] = 0;
    stored[1] = 4095;
    for (std::size_t i = 0; i < stored.size(); ++i)
      ASSERT_EQ(values[k * stored.size() + i], 2.0 * stored[i] - 1024) << k << " " << i;
  }

  // A fractional slope needs floats; they hold these values exactly.
  ScratchDirectory fractional;
  spec.slope = 0.5;
  spec.intercept = 0.25;
  spec.stored = pattern(16, 12, 0);
  spec.position.reset();
  test::write_dicom(fractional / "one.dcm", spec);
  DicomSeriesSource floats = open_series(fractional.path().string());
  EXPECT_EQ(floats.info().type, SampleType::f32);
  EXPECT_EQ(read_values(floats)[37], 0.5 * pattern(16, 12, 0)[37] + 0.25);
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
// Transfer syntaxes

class DicomTransferSyntax : public ::testing::TestWithParam<const char*> {};

TEST_P(DicomTransferSyntax, ReadsBackEqualToTheUncompressedSeries) {
  ScratchDirectory plain, recoded;
  DicomSliceSpec spec;
  spec.width = 33;  // codecs work in blocks; odd sizes exercise the edges
  spec.height = 24;
  spec.bits_stored = 12;
  spec.is_signed = true;  // negative values through every codec
  for (int k = 0; k < 3; ++k) {
    spec.position = Vec3{0, 0, 2.0 * k};
    spec.stored = pattern(33, 24, k, -1500);
    const std::string name = "s" + std::to_string(k) + ".dcm";
    test::write_dicom(plain / name, spec);
    ASSERT_TRUE(test::recode(plain / name, recoded / name, GetParam()));
  }
  DicomSeriesSource original = open_series(plain.path().string());
  DicomSeriesSource copy = open_series(recoded.path().string());
  EXPECT_EQ(copy.plan().headers.front().transfer_syntax_uid, GetParam());
  EXPECT_EQ(copy.info().type, SampleType::i16);
  EXPECT_EQ(copy.info().depth, 3u);
  const std::vector<double> expected = read_values(original);
  EXPECT_EQ(expected[0], -1500);
  EXPECT_EQ(read_values(copy), expected);
}

INSTANTIATE_TEST_SUITE_P(Lossless, DicomTransferSyntax,
                         ::testing::Values(test::kImplicitLittleEndianUid,
                                           test::kExplicitBigEndianUid, test::kRleLosslessUid,
                                           test::kJpegLosslessUid, test::kJpegLsLosslessUid,
                                           test::kJpeg2000LosslessUid));

TEST(DicomSeries, ATransferSyntaxGdcmCannotDecodeIsNamedWithTheFile) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.width = spec.height = 16;
  spec.stored = pattern(16, 16, 0);
  test::write_dicom(dir / "plain.dcm", spec);
  ASSERT_TRUE(test::recode(dir / "plain.dcm", dir / "lossless.dcm", test::kJpegLosslessUid));
  // The same fragments under the transfer syntax of MPEG-2 video, which GDCM has no codec for.
  // Its UID is two bytes longer (with padding), so the element's length and the file meta
  // group's length (the first element after the preamble, PS3.10 7.1) grow by two.
  std::ifstream in(dir / "lossless.dcm", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string jpeg = test::kJpegLosslessUid;  // 22 characters, no padding
  const std::string mpeg("1.2.840.10008.1.2.4.100\0", 24);
  const std::size_t at = bytes.find(jpeg);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(bytes.substr(at - 4, 4), std::string("UI\x16\x00", 4));  // explicit VR, length 22
  bytes.replace(at, jpeg.size(), mpeg);
  bytes[at - 2] = 24;
  ASSERT_EQ(bytes.substr(132, 6), std::string("\x02\x00\x00\x00UL", 6));
  bytes[140] = static_cast<char>(static_cast<unsigned char>(bytes[140]) + 2);
  fs::remove(dir / "plain.dcm");
  fs::remove(dir / "lossless.dcm");
  std::ofstream(dir / "video.dcm", std::ios::binary) << bytes;

  DicomSeriesSource source = open_series(dir.path().string());
  SliceView slice;
  expect_error([&] { source.next_slice(&slice); }, dir / "video.dcm",
               "cannot decode its pixel data (transfer syntax MPEG2");
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

// Every shorter prefix of a file, in several encodings, is refused naming it: the walk in
// dicom_file_scan.cpp keeps GDCM (which aborts on a cut element) from ever seeing one.
TEST(DicomSeries, EveryTruncationOfAFileIsRefusedNamingIt) {
  ScratchDirectory source_dir;
  DicomSliceSpec spec;
  spec.position = Vec3{0, 0, 0};
  spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  spec.stored = pattern(16, 12, 0);
  test::write_dicom(source_dir / "native.dcm", spec);
  spec.transfer_syntax_uid = test::kImplicitLittleEndianUid;
  test::write_dicom(source_dir / "implicit.dcm", spec);
  spec.transfer_syntax_uid = test::kExplicitBigEndianUid;
  test::write_dicom(source_dir / "big.dcm", spec);
  ASSERT_TRUE(
      test::recode(source_dir / "native.dcm", source_dir / "rle.dcm", test::kRleLosslessUid));

  for (const char* name : {"native.dcm", "implicit.dcm", "big.dcm", "rle.dcm"}) {
    ScratchDirectory dir;
    const std::string whole = source_dir / name;
    const std::uintmax_t size = fs::file_size(whole);
    // Two intact neighbours, so a file that silently dropped out would still give a volume.
    spec.transfer_syntax_uid = test::kExplicitLittleEndianUid;
    spec.position = Vec3{0, 0, -1};
    test::write_dicom(dir / "before.dcm", spec);
    spec.position = Vec3{0, 0, 1};
    test::write_dicom(dir / "next.dcm", spec);
    const std::string cut = dir / "cut.dcm";
    int refused = 0;
    for (std::uintmax_t bytes = 0; bytes < size; ++bytes) {
      truncate_copy(whole, cut, bytes);
      try {
        DicomSeriesSource source = open_series(dir.path().string());
        read_values(source);
        ADD_FAILURE() << name << " cut to " << bytes << " of " << size << " bytes was read";
      } catch (const Error& e) {
        if (e.subject() == cut)
          ++refused;
        else
          ADD_FAILURE() << name << " cut to " << bytes << ": " << e.what();
      }
    }
    EXPECT_EQ(refused, static_cast<int>(size)) << name;
  }
}

TEST(DicomSeries, AFileTruncatedAfterPlanningIsRefusedWhenItsSliceIsRead) {
  ScratchDirectory dir;
  write_series(dir.path().string(), "s", DicomSliceSpec{}, 3, {0, 0, 0}, 1);
  DicomSeriesSource source = open_series(dir.path().string());
  const std::string victim = dir / "s1.dcm";
  const std::string whole = dir / "whole.bin";
  fs::copy_file(victim, whole);
  truncate_copy(whole, victim, fs::file_size(whole) - 100);
  SliceView slice;
  ASSERT_TRUE(source.next_slice(&slice));
  expect_error([&] { source.next_slice(&slice); }, victim, "truncated DICOM file");
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void put_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

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
    std::string bytes = file_bytes(one / "image.dcm");
    ASSERT_TRUE(c.corrupt(bytes));
    put_bytes(one / "image.dcm", bytes);
    expect_error([&] { open_series(one.path().string()); }, one / "image.dcm", c.words);
  }
  // RLE: 16-bit samples need two segments; the header says one.
  ScratchDirectory rle;
  ASSERT_TRUE(test::recode(dir / "plain.dcm", rle / "image.dcm", test::kRleLosslessUid));
  std::string bytes = file_bytes(rle / "image.dcm");
  const std::size_t header = bytes.find(std::string("\x02\x00\x00\x00\x40\x00\x00\x00", 8));
  ASSERT_NE(header, std::string::npos);
  bytes[header] = 1;
  put_bytes(rle / "image.dcm", bytes);
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
    std::string bytes = file_bytes(one / "image.dcm");
    // Rows (0028,0010) and Columns (0028,0011), explicit VR US: 4000 each, 32 MB a frame.
    for (const char element : {'\x10', '\x11'}) {
      const std::size_t at =
          bytes.find(std::string("\x28\x00", 2) + element + std::string("\x00US\x02\x00", 5));
      ASSERT_NE(at, std::string::npos);
      bytes[at + 8] = static_cast<char>(4000 & 0xff);
      bytes[at + 9] = static_cast<char>(4000 >> 8);
    }
    put_bytes(one / "image.dcm", bytes);
    expect_error([&] { open_series(one.path().string()); }, one / "image.dcm",
                 "bytes of compressed data cannot hold a 4000x4000 frame of 32000000 bytes");
  }
}

// GDCM asserts when an element it reads has another VR than the standard's, or an unknown one.
TEST(DicomSeries, ElementsWithWrongOrUnknownVrsAreRefused) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.stored = pattern(16, 12, 0);
  test::write_dicom(dir / "plain.dcm", spec);
  const std::string plain = file_bytes(dir / "plain.dcm");
  fs::remove(dir / "plain.dcm");
  const std::string rows("\x28\x00\x10\x00US", 6);  // (0028,0010) US, explicit little endian
  const std::size_t at = plain.find(rows);
  ASSERT_NE(at, std::string::npos);
  std::string wrong = plain, unknown = plain, recognition = plain;
  wrong[at + 5] = 'L';    // UL: a real VR, not Rows'
  unknown[at + 5] = 'H';  // UH: no such VR
  const std::size_t modality =
      plain.find(std::string("\x08\x00\x60\x00"
                             "CS",
                             6));
  ASSERT_NE(modality, std::string::npos);
  recognition[modality + 2] = 0x10;  // (0008,0060) Modality becomes (0008,0010) RecognitionCode
  recognition[modality + 4] = 'S';
  recognition[modality + 5] = 'H';
  put_bytes(dir / "image.dcm", wrong);
  expect_error([&] { open_series(dir.path().string()); }, dir / "image.dcm",
               "element (0028,0010) at byte " + std::to_string(at) + " has VR UL, expected US");
  put_bytes(dir / "image.dcm", unknown);
  expect_error([&] { open_series(dir.path().string()); }, dir / "image.dcm", "unknown VR UH");
  put_bytes(dir / "image.dcm", recognition);
  expect_error([&] { open_series(dir.path().string()); }, dir / "image.dcm",
               "(RecognitionCode) does not name ACR-NEMA");
}

// Random byte changes in files of every encoding: each is read or refused with an mvox::Error
// naming it; none may crash the process (which would end this test binary). Fixed seed.
TEST(DicomSeries, CorruptedBytesAreReadOrRefusedNeverACrash) {
  ScratchDirectory originals;
  DicomSliceSpec spec;
  spec.width = 24;
  spec.height = 20;
  spec.position = Vec3{0, 0, 0};
  spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  spec.slope = 1;
  spec.intercept = -1024;
  spec.stored = pattern(24, 20, 0);
  test::write_dicom(originals / "explicit.dcm", spec);
  spec.transfer_syntax_uid = test::kImplicitLittleEndianUid;
  test::write_dicom(originals / "implicit.dcm", spec);
  spec.transfer_syntax_uid = test::kExplicitBigEndianUid;
  test::write_dicom(originals / "big.dcm", spec);
  std::vector<std::string> files = {"explicit.dcm", "implicit.dcm", "big.dcm"};
  for (const char* syntax : {test::kRleLosslessUid, test::kJpegLosslessUid,
                             test::kJpegLsLosslessUid, test::kJpeg2000LosslessUid}) {
    files.push_back(std::string(syntax) + ".dcm");
    ASSERT_TRUE(test::recode(originals / "explicit.dcm", originals / files.back(), syntax));
  }
  std::mt19937 random(20240611);
  ScratchDirectory dir;
  const std::string victim = dir / "case.dcm";
  int read = 0, refused = 0;
  for (int trial = 0; trial < 1400; ++trial) {
    std::string bytes = file_bytes(originals / files[trial % files.size()]);
    const int changes = 1 + static_cast<int>(random() % 4);
    for (int c = 0; c < changes; ++c) bytes[random() % bytes.size()] = static_cast<char>(random());
    put_bytes(victim, bytes);
    try {
      DicomSeriesSource source({victim}, DicomOptions{});
      read_values(source);
      ++read;
    } catch (const Error& e) {
      ++refused;
      EXPECT_TRUE(e.subject() == victim) << e.what();
      const std::string what = e.what();
      EXPECT_TRUE(std::all_of(what.begin(), what.end(), [](char c) { return c >= 32 && c < 127; }))
          << what;
    }
  }
  EXPECT_GT(read, 200);  // most changes hit pixel values, which are read as they are
  EXPECT_GT(refused, 200);
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

// ---------------------------------------------------------------------------------------------
// The command line

bool position_less(const Vertex& a, const Vertex& b) {
  return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
}

// Writes a sphere phantom as a DICOM series with the given row and column cosines, extracts it
// through the command line, and checks the mesh: closed, outward, and every vertex in patient
// coordinates, origin + row * column spacing * x + column * row spacing * y + normal * gap * z.
void expect_sphere_series_in_patient_coordinates(const Vec3& row, const Vec3& column) {
  ScratchDirectory dir;
  fs::create_directory(dir / "scans");
  const sim::Grid grid{22, 19, 17};
  const sim::Sphere sphere(grid, sim::grid_centre(grid), 7.2);
  const Vec3 origin{-10, 20, 30};
  const Vec3 normal{row[1] * column[2] - row[2] * column[1],
                    row[2] * column[0] - row[0] * column[2],
                    row[0] * column[1] - row[1] * column[0]};
  const double gap = 1.5;
  DicomSliceSpec spec;
  spec.width = grid.width;
  spec.height = grid.height;
  spec.bits_stored = 12;
  spec.intercept = -1024;  // stored 24 is air (-1000 HU), 1100 is bone-like (76 HU)
  spec.pixel_spacing = std::array<double, 2>{0.6, 0.8};  // rows 0.6 apart, columns 0.8
  spec.orientation = std::array<double, 6>{row[0], row[1], row[2], column[0], column[1], column[2]};
  test::BinaryVolume inner(grid.width, grid.height, grid.depth);
  for (std::uint32_t z = 0; z < grid.depth; ++z) {
    spec.position = Vec3{origin[0] + normal[0] * z * gap, origin[1] + normal[1] * z * gap,
                         origin[2] + normal[2] * z * gap};
    spec.instance_number = grid.depth - z;  // numbered backwards, named shuffled
    spec.stored.clear();
    for (std::uint32_t y = 0; y < grid.height; ++y)
      for (std::uint32_t x = 0; x < grid.width; ++x) {
        const bool in = sphere.density(x, y, z) > 0.5f;
        inner.at(x, y, z) = in;
        spec.stored.push_back(in ? 1100 : 24);
      }
    test::write_dicom(dir / ("scans/IM" + std::to_string((z * 7) % grid.depth) + ".dcm"), spec);
  }

  const auto result = run_mvox("extract scans -t 0 -o sphere.ply -q", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, "");  // quiet: not even the PixelSpacing or series notes
  const test::Mesh mesh = test::to_mesh(read_ply(dir / "sphere.ply"));
  const test::Topology topology = test::analyse(mesh);
  EXPECT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
  EXPECT_EQ(topology.euler(), 2);
  EXPECT_EQ(topology.components, 1u);
  EXPECT_GT(topology.signed_volume, 0);  // outward in patient space too

  std::vector<Vertex> expected = test::expected_vertices(inner);
  const double spacing[3] = {0.8, 0.6, gap};
  const Vec3 axes[3] = {row, column, normal};
  for (Vertex& v : expected) {
    const double voxel[3] = {v.x, v.y, v.z};
    double world[3] = {origin[0], origin[1], origin[2]};
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) world[k] += axes[a][k] * spacing[a] * voxel[a];
    v.x = static_cast<float>(world[0]);
    v.y = static_cast<float>(world[1]);
    v.z = static_cast<float>(world[2]);
  }
  std::vector<Vertex> actual = mesh.vertices;
  std::sort(expected.begin(), expected.end(), position_less);
  std::sort(actual.begin(), actual.end(), position_less);
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i) {
    ASSERT_NEAR(actual[i].x, expected[i].x, 1e-4) << i;
    ASSERT_NEAR(actual[i].y, expected[i].y, 1e-4) << i;
    ASSERT_NEAR(actual[i].z, expected[i].z, 1e-4) << i;
  }
}

TEST(DicomCli, AxialSphereSeriesGivesAClosedSphereWhereTheHeaderPutsIt) {
  expect_sphere_series_in_patient_coordinates({1, 0, 0}, {0, 1, 0});
}

TEST(DicomCli, ObliqueSphereSeriesIsPlacedAlongItsOrientationInPatientCoordinates) {
  // Rows turned 30 degrees about z, then the plane tipped 20 degrees about the row direction.
  const double a = 30 * M_PI / 180, b = 20 * M_PI / 180;
  const Vec3 row{std::cos(a), std::sin(a), 0};
  const Vec3 column{-std::sin(a) * std::cos(b), std::cos(a) * std::cos(b), std::sin(b)};
  expect_sphere_series_in_patient_coordinates(row, column);
}

TEST(DicomCli, SeriesNotesErrorsAndHelp) {
  ScratchDirectory dir;
  fs::create_directory(dir / "scans");
  DicomSliceSpec a, b;
  a.series_uid = "1.2.826.0.1.3680043.10.543.21";
  b.series_uid = "1.2.826.0.1.3680043.10.543.22";
  a.pixel_spacing = b.pixel_spacing = std::array<double, 2>{1, 1};
  write_series((dir / "scans"), "a", a, 3, {0, 0, 0}, 1);
  write_series((dir / "scans"), "b", b, 2, {0, 0, 0}, 1);

  // Not quiet: one note line about the series, then the summary.
  auto noted = run_mvox("extract scans -t 100 -o a.ply", dir.path());
  ASSERT_EQ(noted.exit_code, 0) << noted.output;
  EXPECT_EQ(noted.output.rfind("mvox: note: scans: 2 DICOM series; reading the largest, " +
                                   a.series_uid + " (3 slices); also " + b.series_uid +
                                   " (2 slices); choose one with --series UID\n",
                               0),
            0u)
      << noted.output;
  auto picked = run_mvox("extract scans -t 100 -o b.ply -q --stats b.json --series " + b.series_uid,
                         dir.path());
  ASSERT_EQ(picked.exit_code, 0) << picked.output;
  std::ifstream stats(dir / "b.json");
  const std::string json((std::istreambuf_iterator<char>(stats)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"dimensions\": [16, 12, 2]"), std::string::npos) << json;

  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply --series 9.9", dir.path()),
                        "--series: no series 9.9 in scans; it holds " + a.series_uid);
  // Two slices in one place: refused before any output appears.
  DicomSliceSpec twin = a;
  twin.position = Vec3{0, 0, 1};
  test::write_dicom(dir / "scans/a9.dcm", twin);
  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply", dir.path()), "scans/a9.dcm");
  // A threshold beyond the 16-bit unsigned samples is refused as for any input.
  fs::remove(dir / "scans/a9.dcm");
  expect_one_line_error(run_mvox("extract scans -t 70000 -o x.ply", dir.path()), "scans");
  EXPECT_EQ(dir.listing(), "a.ply b.json b.ply scans ");

  const auto help = run_mvox("extract --help", dir.path());
  EXPECT_NE(help.output.find("DICOM"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--series"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--dicom"), std::string::npos) << help.output;
}

// An entry of the series' folder that cannot be read is named, as in an image stack, rather
// than hiding the series (the folder was then read as images and said to hold none).
TEST(DicomCli, AFifoOrADanglingLinkBesideTheSeriesIsNamed) {
  ScratchDirectory dir;
  fs::create_directory(dir / "scans");
  DicomSliceSpec spec;
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  write_series((dir / "scans"), "a", spec, 3, {0, 0, 0}, 1);
  ASSERT_EQ(::mkfifo((dir / "scans/pipe").c_str(), 0600), 0);
  // Never opened: with no writer, opening the FIFO would wait forever.
  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply", dir.path()),
                        "mvox: error: scans/pipe: is not a regular file (a FIFO, socket or "
                        "device), not a slice");
  fs::remove(dir / "scans/pipe");
  fs::create_symlink("gone.dcm", dir / "scans/a7.dcm");
  expect_one_line_error(run_mvox("extract scans -t 100 -o x.ply", dir.path()),
                        "mvox: error: scans/a7.dcm: is a dangling symbolic link");
  expect_one_line_error(run_mvox("extract 'scans/*' -t 100 -o x.ply", dir.path()),
                        "mvox: error: scans/a7.dcm: is a dangling symbolic link");
  EXPECT_EQ(dir.listing(), "scans ");
}

// A spacing or position that float coordinates cannot hold is refused naming the input, and
// called too large (not "must be positive and finite", as 1e300 is both).
TEST(DicomCli, SpacingOrPositionBeyondFloatIsRefusedNamingTheInput) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.pixel_spacing = std::array<double, 2>{1e300, 1};
  fs::create_directory(dir / "wide");
  write_series((dir / "wide"), "a", spec, 3, {0, 0, 0}, 1);
  expect_one_line_error(run_mvox("extract wide -t 100 -o x.ply", dir.path()),
                        "mvox: error: wide: spacing y is too large for float coordinates, got "
                        "1e+300 (usable: 2.35099e-38 to 3.40282e+38)");
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  fs::create_directory(dir / "far");
  write_series((dir / "far"), "a", spec, 3, {0, 1e300, 0}, 1);
  expect_one_line_error(run_mvox("extract far -t 100 --image x.png", dir.path()),
                        "mvox: error: far: origin y is too large for float coordinates, got "
                        "1e+300");
  // Slices 1e300 mm apart: the spacing along the normal.
  fs::create_directory(dir / "apart");
  write_series((dir / "apart"), "a", spec, 3, {0, 0, -1e300}, 1e300);
  expect_one_line_error(run_mvox("extract apart -t 100 -o x.ply", dir.path()),
                        "mvox: error: apart: spacing z is too large for float coordinates");
  EXPECT_EQ(dir.listing(), "apart far wide ");
}

// ---------------------------------------------------------------------------------------------
// Real files from ../shared/datasets

std::string dataset(const std::string& name) {
  return std::string(MVOX_SHARED_DATASETS) + "/" + name;
}

#define MVOX_REQUIRE_DATASET(name) \
  if (!fs::exists(dataset(name)))  \
  GTEST_SKIP() << dataset(name) << " is absent (../shared/datasets is not beside the checkout)"

// The slice normal and a file's position along it, read with GDCM: an oracle independent of
// mvox's header parsing.
double gdcm_position_along_normal(const std::string& path) {
  gdcm::Reader reader;
  reader.SetFileName(path.c_str());
  EXPECT_TRUE(reader.Read()) << path;
  const gdcm::DataSet& ds = reader.GetFile().GetDataSet();
  gdcm::Attribute<0x0020, 0x0032> position;
  gdcm::Attribute<0x0020, 0x0037> orientation;
  position.SetFromDataSet(ds);
  orientation.SetFromDataSet(ds);
  const Vec3 normal = cross({orientation[0], orientation[1], orientation[2]},
                            {orientation[3], orientation[4], orientation[5]});
  return dot({position[0], position[1], position[2]}, normal);
}

TEST(DicomDatasets, BbmriSixObliqueSlicesNineMillimetresApart) {
  MVOX_REQUIRE_DATASET("dicom_mr_bbmri_6slices");
  DicomSeriesSource source = open_series(dataset("dicom_mr_bbmri_6slices"));
  const VolumeInfo& info = source.info();
  EXPECT_EQ(info.width, 256u);
  EXPECT_EQ(info.height, 256u);
  EXPECT_EQ(info.depth, 6u);
  EXPECT_EQ(info.type, SampleType::u16);  // 12-bit unsigned, no rescale
  EXPECT_NEAR(info.spacing[0], 1, 1e-9);
  EXPECT_NEAR(info.spacing[1], 1, 1e-9);
  EXPECT_NEAR(info.spacing[2], 9, 1e-6);
  // INFO.txt: positions along the normal -16.248 .. 28.752 in 9 mm steps.
  const auto& slices = source.plan().slices;
  EXPECT_NEAR(slices.front().position_mm, -16.248, 1e-3);
  EXPECT_NEAR(slices.back().position_mm, 28.752, 1e-3);
  double previous = -std::numeric_limits<double>::infinity();
  for (const DicomSliceRef& slice : slices) {
    const std::string& path = source.plan().headers[slice.header].path;
    const double along = gdcm_position_along_normal(path);
    EXPECT_NEAR(along, slice.position_mm, 1e-6) << path;
    EXPECT_GT(along, previous) << path;
    previous = along;
  }
  // The axes: oblique, orthonormal, right-handed.
  const Vec3 x{info.axes[0][0], info.axes[0][1], info.axes[0][2]};
  const Vec3 y{info.axes[1][0], info.axes[1][1], info.axes[1][2]};
  const Vec3 z{info.axes[2][0], info.axes[2][1], info.axes[2][2]};
  EXPECT_NEAR(dot(x, y), 0, 1e-6);
  EXPECT_NEAR(dot(cross(x, y), z), 1, 1e-6);
  EXPECT_GT(std::fabs(x[1]), 0.9);  // rows run mostly anterior-posterior: sagittal slices
  const std::vector<double> values = read_values(source);
  EXPECT_EQ(*std::min_element(values.begin(), values.end()), 0);
  EXPECT_EQ(*std::max_element(values.begin(), values.end()), 1398);
}

TEST(DicomDatasets, BbmriExtractedEndToEndIsAClosedSurface) {
  MVOX_REQUIRE_DATASET("dicom_mr_bbmri_6slices");
  ScratchDirectory dir;
  const auto result = run_mvox(
      "extract '" + dataset("dicom_mr_bbmri_6slices") + "' -t 300 -o head.ply -q", dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const test::Topology topology = test::analyse(test::to_mesh(read_ply(dir / "head.ply")));
  EXPECT_TRUE(topology.closed_and_consistent()) << test::describe(topology);
  EXPECT_GT(topology.faces, 10000u);
  EXPECT_GT(topology.signed_volume, 0);
}

TEST(DicomDatasets, CptacScoutThreeAxialSlicesTwelveMillimetresApart) {
  MVOX_REQUIRE_DATASET("dicom_cptac_sar_mr_scout");
  // The folder also holds preview PNGs, INFO.txt and a CSV: skipped by content.
  DicomSeriesSource source = open_series(dataset("dicom_cptac_sar_mr_scout"));
  const VolumeInfo& info = source.info();
  EXPECT_EQ(info.width, 512u);
  EXPECT_EQ(info.depth, 3u);
  EXPECT_EQ(info.spacing[0], 0.9765625);
  EXPECT_EQ(info.spacing[1], 0.9765625);
  EXPECT_NEAR(info.spacing[2], 12, 1e-9);
  // Files 1-1, 1-2, 1-3 are at z = 12, 0, -12: ascending z reads them backwards.
  const char* expected[] = {"1-3.dcm", "1-2.dcm", "1-1.dcm"};
  for (int k = 0; k < 3; ++k) {
    const DicomSliceRef& slice = source.plan().slices[k];
    EXPECT_EQ(fs::path(source.plan().headers[slice.header].path).filename(), expected[k]);
    EXPECT_NEAR(slice.position_mm, -12 + 12 * k, 1e-9);
  }
  EXPECT_EQ(info.origin[0], -250);
  EXPECT_EQ(info.origin[1], -250);
  EXPECT_EQ(info.origin[2], -12);
  const std::vector<double> values = read_values(source);
  EXPECT_EQ(*std::max_element(values.begin(), values.end()), 346);
}

std::vector<double> single_file_values(const std::string& name, VolumeInfo* info = nullptr) {
  DicomSeriesSource source({dataset("dicom_singles/" + name)}, DicomOptions{});
  if (info) *info = source.info();
  EXPECT_EQ(source.info().depth, 1u) << name;
  return read_values(source);
}

TEST(DicomDatasets, SinglesOpenAndAgreeAcrossEncodings) {
  MVOX_REQUIRE_DATASET("dicom_singles");
  for (const auto& entry : fs::directory_iterator(dataset("dicom_singles"))) {
    if (entry.path().extension() != ".dcm") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_FALSE(single_file_values(entry.path().filename().string()).empty());
  }
  // MR_small in explicit little endian, big endian and implicit VR: identical samples.
  VolumeInfo mr;
  const std::vector<double> explicit_le = single_file_values("MR_small.dcm", &mr);
  EXPECT_EQ(mr.type, SampleType::i16);
  EXPECT_EQ(*std::min_element(explicit_le.begin(), explicit_le.end()), 127);
  EXPECT_EQ(*std::max_element(explicit_le.begin(), explicit_le.end()), 2145);
  EXPECT_EQ(single_file_values("MR_small_bigendian.dcm"), explicit_le);
  EXPECT_EQ(single_file_values("MR_small_implicit.dcm"), explicit_le);
  // CT_small stores 128 .. 2191 with RescaleIntercept -1024: Hounsfield units -896 .. 1167.
  VolumeInfo ct;
  const std::vector<double> hu = single_file_values("CT_small.dcm", &ct);
  EXPECT_EQ(ct.type, SampleType::f32);  // 16-bit signed stored, intercept -1024
  EXPECT_EQ(*std::min_element(hu.begin(), hu.end()), 128 - 1024);
  EXPECT_EQ(*std::max_element(hu.begin(), hu.end()), 2191 - 1024);
  EXPECT_NEAR(ct.spacing[0], 0.661468, 1e-6);
  // The 8-bit abdomen CT: u8, the full 0 .. 255.
  VolumeInfo abdo;
  const std::vector<double> eight = single_file_values("gdcm-CT-MONO2-8-abdo.dcm", &abdo);
  EXPECT_EQ(abdo.type, SampleType::u8);
  EXPECT_EQ(abdo.width, 512u);
  EXPECT_EQ(*std::max_element(eight.begin(), eight.end()), 255);
}

}  // namespace
}  // namespace mvox
