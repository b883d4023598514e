// What a DICOM slice's samples come out as (src/read/dicom/dicom_values.h,
// dicom_pixel_reader.h): the smallest exact sample type, RescaleSlope and RescaleIntercept on the
// stored bits alone, and every lossless transfer syntax decoding to the uncompressed series; one
// GDCM cannot decode is named with the file.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "command_runner.h"
#include "dicom_series.h"
#include "dicom_writer.h"
#include "read/dicom/dicom_series_source.h"
#include "read/dicom/dicom_values.h"

namespace mvox {
namespace {

namespace fs = std::filesystem;
using test::DicomSliceSpec;
using test::ScratchDirectory;
using test::dicom_series::expect_error;
using test::dicom_series::open_series;
using test::dicom_series::pattern;
using test::dicom_series::read_values;
using test::dicom_series::Vec3;

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

}  // namespace
}  // namespace mvox
