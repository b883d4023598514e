// The NIfTI reader (read/nifti/): every sample type it takes, in both byte orders, NIfTI-1 and
// NIfTI-2, as .nii, .nii.gz and .hdr/.img; scl_slope and scl_inter; the sform, the qform and
// the voxel sizes placing the volume; and every malformed header refused with one line naming
// the file. The files are written field by field (tests/support/nifti_files.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error.h"
#include "nifti_files.h"
#include "read/input_format.h"
#include "volume_files.h"

namespace mvox {
namespace {

using test::NiftiFile;
using test::ScratchDirectory;
using test::write_nifti;
using test::volume_files::expect_axes;
using test::volume_files::read_volume;

constexpr std::uint32_t kW = 5, kH = 4, kD = 3;
constexpr std::size_t kCount = kW * kH * kD;

NiftiFile volume_of(std::int16_t datatype, std::int16_t bitpix,
                    const std::vector<unsigned char>& samples) {
  NiftiFile file;
  file.dim[0] = 3;
  file.dim[1] = kW;
  file.dim[2] = kH;
  file.dim[3] = kD;
  file.datatype = datatype;
  file.bitpix = bitpix;
  file.samples = samples;
  return file;
}

// Values that need every bit of their type somewhere: extremes and a ramp.
template <class T>
std::vector<T> values_for(double low, double high) {
  std::vector<T> values(kCount);
  for (std::size_t i = 0; i < kCount; ++i)
    values[i] = static_cast<T>(low + (high - low) * static_cast<double>(i) / (kCount - 1));
  return values;
}

struct Container {
  const char* name;
  bool gzip, pair;
};
constexpr Container kContainers[] = {
    {"v.nii", false, false}, {"v.nii.gz", true, false}, {"v.hdr", false, true},
    {"w.hdr", true, true}};  // w.img.gz

// Writes `file` in every container, version and byte order, and checks the samples read.
template <class Read, class Stored>
void expect_round_trip(NiftiFile file, const std::vector<Stored>& stored,
                       const std::vector<Read>& expected, SampleType engine_type) {
  file.samples = test::sample_bytes_of(stored);
  for (const int version : {1, 2})
    for (const bool big : {false, true})
      for (const Container& container : kContainers) {
        SCOPED_TRACE(std::string(container.name) + " NIfTI-" + std::to_string(version) +
                     (big ? " big-endian" : " little-endian"));
        ScratchDirectory dir;
        file.version = version;
        file.big_endian = big;
        file.gzip = container.gzip;
        file.pair = container.pair;
        write_nifti(dir / container.name, file);
        VolumeInfo info;
        const std::vector<Read> read = read_volume<Read>(dir / container.name, &info);
        EXPECT_EQ(info.width, kW);
        EXPECT_EQ(info.height, kH);
        EXPECT_EQ(info.depth, kD);
        EXPECT_EQ(info.type, engine_type);
        EXPECT_EQ(read, expected);
      }
}

TEST(NiftiReader, EverySampleTypeInEveryContainerVersionAndByteOrder) {
  {
    const auto v = values_for<std::uint8_t>(0, 255);
    expect_round_trip(volume_of(2, 8, {}), v, v, SampleType::u8);
  }
  {
    const auto v = values_for<std::int8_t>(-128, 127);
    expect_round_trip(volume_of(256, 8, {}), v, std::vector<std::int16_t>(v.begin(), v.end()),
                      SampleType::i16);
  }
  {
    const auto v = values_for<std::uint16_t>(0, 65535);
    expect_round_trip(volume_of(512, 16, {}), v, v, SampleType::u16);
  }
  {
    const auto v = values_for<std::int16_t>(-32768, 32767);
    expect_round_trip(volume_of(4, 16, {}), v, v, SampleType::i16);
  }
  {
    // Label maps in int32: exact in float up to 2^24.
    const auto v = values_for<std::int32_t>(-16777216, 16777216);
    expect_round_trip(volume_of(8, 32, {}), v, std::vector<float>(v.begin(), v.end()),
                      SampleType::f32);
  }
  {
    const auto v = values_for<std::uint32_t>(0, 16777216);
    expect_round_trip(volume_of(768, 32, {}), v, std::vector<float>(v.begin(), v.end()),
                      SampleType::f32);
  }
  {
    const auto v = values_for<float>(-1e30, 3.5e30);
    expect_round_trip(volume_of(16, 32, {}), v, v, SampleType::f32);
  }
  {
    const auto v = values_for<double>(-1000.25, 2000.5);
    std::vector<float> expected(v.begin(), v.end());
    expect_round_trip(volume_of(64, 64, {}), v, expected, SampleType::f32);
  }
}

TEST(NiftiReader, Int32SamplesThatAFloatCannotHoldAreRefused) {
  // 16777217 would become 16777216 as a float: two labels merged without a word.
  std::vector<std::int32_t> values(kCount, 3);
  values[kCount - 1] = 16777217;
  NiftiFile file = volume_of(8, 32, test::sample_bytes_of(values));
  ScratchDirectory dir;
  write_nifti(dir / "big.nii", file);
  try {
    read_volume<float>(dir / "big.nii");
    ADD_FAILURE() << "read";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("holds 16777217, beyond 16777216"), std::string::npos)
        << error.what();
  }
}

TEST(NiftiReader, SclSlopeAndSclInterScaleTheSamplesToFloat) {
  const auto stored = values_for<std::int16_t>(-100, 3000);
  NiftiFile file = volume_of(4, 16, {});
  file.scl_slope = 2;
  file.scl_inter = -1024;
  std::vector<float> expected;
  for (const std::int16_t value : stored) expected.push_back(2.0f * value - 1024.0f);
  expect_round_trip(file, stored, expected, SampleType::f32);
  // A slope of 0 means no scaling, whatever the intercept: the samples keep their type.
  file.scl_slope = 0;
  file.scl_inter = 5;
  expect_round_trip(file, stored, stored, SampleType::i16);
}

VolumeInfo info_of(const NiftiFile& file) {
  ScratchDirectory dir;
  write_nifti(dir / "g.nii", file);
  return open_slice_source({dir / "g.nii"}, std::nullopt)->info();
}

TEST(NiftiReader, TheSformPlacesTheVolumeWhenItsCodeIsSet) {
  NiftiFile file = volume_of(2, 8, std::vector<unsigned char>(kCount));
  file.sform_code = 1;
  file.qform_code = 1;  // the sform wins
  file.quatern[2] = 1;
  const double srow[3][4] = {{-2, 0, 0, 10}, {0, 0, 3, 20}, {0, 4, 0, -30}};
  std::memcpy(file.srow, srow, sizeof srow);
  for (const int version : {1, 2}) {
    file.version = version;
    const VolumeInfo info = info_of(file);
    expect_axes(info, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {2, 4, 3});
    EXPECT_DOUBLE_EQ(info.origin[0], 10);
    EXPECT_DOUBLE_EQ(info.origin[1], 20);
    EXPECT_DOUBLE_EQ(info.origin[2], -30);
  }
}

TEST(NiftiReader, TheQformTurnsByItsQuaternionAndQfacFlipsTheSliceAxis) {
  // 90 degrees about z: (b, c, d) = (0, 0, sin 45); voxels 1, 2, 3; qfac -1.
  NiftiFile file = volume_of(2, 8, std::vector<unsigned char>(kCount));
  file.qform_code = 1;
  file.quatern[2] = std::sqrt(0.5);
  file.quatern[3] = 7;
  file.quatern[4] = -8;
  file.quatern[5] = 9;
  file.pixdim[0] = -1;
  file.pixdim[1] = 1;
  file.pixdim[2] = 2;
  file.pixdim[3] = 3;
  for (const int version : {1, 2}) {
    file.version = version;
    const VolumeInfo info = info_of(file);
    // NIfTI-1 keeps the quaternion in floats: sin 45 degrees to 7 digits.
    const double axes[3][3] = {{0, 1, 0}, {-1, 0, 0}, {0, 0, -1}}, spacing[3] = {1, 2, 3};
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(info.spacing[a], spacing[a], 1e-6) << a;
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(info.axes[a][i], axes[a][i], 1e-6) << a << "," << i;
    }
    EXPECT_NEAR(info.origin[0], 7, 1e-6);
    EXPECT_NEAR(info.origin[1], -8, 1e-6);
    EXPECT_NEAR(info.origin[2], 9, 1e-6);
  }
}

TEST(NiftiReader, WithoutTransformsTheVoxelSizesPlaceItAndUnitsBecomeMillimetres) {
  NiftiFile file = volume_of(2, 8, std::vector<unsigned char>(kCount));
  file.pixdim[1] = 0.5;
  file.pixdim[2] = 0.75;
  file.pixdim[3] = 2;
  expect_axes(info_of(file), {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0.5, 0.75, 2});
  file.xyzt_units = 1;  // metres
  file.pixdim[1] = 0.001;
  file.pixdim[2] = 0.002;
  file.pixdim[3] = 0.004;
  const VolumeInfo info = info_of(file);
  EXPECT_NEAR(info.spacing[0], 1, 1e-6);
  EXPECT_NEAR(info.spacing[1], 2, 1e-6);
  EXPECT_NEAR(info.spacing[2], 4, 1e-6);
}

// Every malformed file: one line naming the file and the problem.
void expect_refused(const NiftiFile& file, const std::string& name, const std::string& problem) {
  ScratchDirectory dir;
  write_nifti(dir / name, file);
  try {
    open_slice_source({dir / name}, std::nullopt)->info();
    auto source = open_slice_source({dir / name}, std::nullopt);
    SliceView slice;
    while (source->next_slice(&slice)) {
    }
    ADD_FAILURE() << name << " was read; expected: " << problem;
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(problem), std::string::npos) << message;
    EXPECT_NE(message.find(name.substr(0, name.find('.'))), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(NiftiReader, MalformedHeadersAreRefusedWithOneLineNamingTheFile) {
  const std::vector<unsigned char> samples(kCount);
  const NiftiFile good = volume_of(2, 8, samples);
  for (const int version : {1, 2}) {
    SCOPED_TRACE("NIfTI-" + std::to_string(version));
    NiftiFile f = good;
    f.version = version;
    NiftiFile bad = f;
    bad.dim[0] = 4;
    bad.dim[4] = 2;
    bad.samples.resize(2 * kCount);
    expect_refused(bad, "four.nii", "4-D image of 2 volumes of 5x4x3 voxels");
    bad = f;
    bad.magic = version == 1 ? std::string("abc", 4) : std::string("abcdefgh", 8);
    expect_refused(bad, "magic.nii", "magic");
    bad = f;
    bad.datatype = 32;
    bad.bitpix = 64;
    expect_refused(bad, "complex.nii", "datatype complex64 (32): mvox reads");
    bad = f;
    bad.datatype = 3;
    expect_refused(bad, "unknown.nii", "datatype 3 is not a NIfTI data type");
    bad = f;
    bad.bitpix = 16;
    expect_refused(bad, "bitpix.nii", "bitpix is 16, but datatype uint8 has 8 bits");
    bad = f;
    bad.vox_offset = 100;
    expect_refused(bad, "offset.nii", "vox_offset is 100");
    bad = f;
    bad.dim[0] = 0;
    expect_refused(bad, "nodims.nii", "dim[0] is 0");
    bad = f;
    bad.dim[2] = version == 1 ? -3 : 0;
    expect_refused(bad, "negative.nii", "dim[2] is");
    bad = f;
    bad.pixdim[2] = 0;
    expect_refused(bad, "flat.nii", "pixdim[2] is 0");
    bad = f;
    bad.scl_slope = INFINITY;
    expect_refused(bad, "scale.nii", "the scaling must be finite");
    bad = f;
    bad.sform_code = 1;
    bad.srow[1][1] = NAN;
    expect_refused(bad, "sform.nii", "sform gives voxel axis j no direction");
    // A subnormal column (NIfTI-2's doubles can hold one) gives no unit direction either.
    bad.srow[1][1] = version == 2 ? 1e-320 : 0.0;
    expect_refused(bad, "tiny.nii", "sform gives voxel axis j no direction");
    bad = f;
    bad.samples.resize(kCount - 7);
    expect_refused(bad, "short.nii", "expected");
    bad = f;
    bad.pair = true;
    expect_refused(bad, "pair.nii", "name it .hdr");
  }
}

TEST(NiftiReader, FilesThatAreNotNiftiOrEndEarlyAreRefused) {
  ScratchDirectory dir;
  test::volume_files::write_file(dir / "text.nii", std::string(400, 'x'));
  test::volume_files::write_file(dir / "tiny.nii", "ab");
  std::vector<unsigned char> header = test::nifti_header_bytes(volume_of(2, 8, {}));
  header.resize(200);
  test::volume_files::write_file(dir / "cut.nii", "", header);
  NiftiFile pair = volume_of(2, 8, std::vector<unsigned char>(kCount));
  pair.pair = true;
  write_nifti(dir / "lonely.hdr", pair);
  std::filesystem::remove(dir / "lonely.img");
  test::volume_files::write_file(dir / "broken.nii.gz", "not gzip at all, but long enough");
  const std::pair<const char*, const char*> cases[] = {
      {"text.nii", "neither 348 (NIfTI-1) nor 540 (NIfTI-2)"},
      {"tiny.nii", "too short for a NIfTI header"},
      {"cut.nii", "inside its 348-byte NIfTI header"},
      {"lonely.hdr", "lonely.img does not exist"},
      {"broken.nii.gz", "broken.nii.gz"},
  };
  for (const auto& [name, problem] : cases) {
    try {
      open_slice_source({dir / name}, std::nullopt);
      ADD_FAILURE() << name << " was opened";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(problem), std::string::npos) << error.what();
    }
  }
}

}  // namespace
}  // namespace mvox
