// --tissue: CT presets in Hounsfield units. Bone and skin are thresholds (the same mesh as -t
// 300 and -t -300); fat and soft tissue are ranges (the surface of the voxels inside the range,
// the same mesh as -t 1 on that range's 0/1 mask). Accepted for CT DICOM series and, with --hu,
// for any input; refused otherwise with one line.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "command_runner.h"
#include "dicom_writer.h"
#include "file_io.h"
#include "nifti_files.h"
#include "volume_files.h"

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;

constexpr int kW = 20, kH = 18, kD = 14;

// Hounsfield units of a small "body": air, a ball of fat, soft tissue inside it, bone inside that.
std::int64_t hounsfield(int x, int y, int z) {
  const int d2 = (x - 10) * (x - 10) + (y - 9) * (y - 9) + (z - 7) * (z - 7);
  return d2 <= 4 ? 700 : d2 <= 16 ? 40 : d2 <= 36 ? -100 : -1000;
}

// The series as a CT scanner stores it: values + 1024, RescaleIntercept -1024.
void write_ct_series(const ScratchDirectory& dir, const std::string& modality) {
  std::filesystem::create_directories(dir / "series");
  for (int z = 0; z < kD; ++z) {
    test::DicomSliceSpec spec;
    spec.width = kW;
    spec.height = kH;
    spec.modality = modality;
    spec.intercept = -1024;
    spec.slope = 1;
    spec.position = std::array<double, 3>{0, 0, static_cast<double>(z)};
    spec.instance_number = z + 1;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) spec.stored.push_back(hounsfield(x, y, z) + 1024);
    test::write_dicom(dir / ("series/s" + std::to_string(z) + ".dcm"), spec);
  }
}

// The same values as a raw i16 volume, and the 0/1 mask of [low, high] as raw u8.
void write_raw(const ScratchDirectory& dir, int low, int high) {
  std::vector<std::int16_t> values;
  std::vector<unsigned char> mask;
  for (int z = 0; z < kD; ++z)
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const auto v = static_cast<std::int16_t>(hounsfield(x, y, z));
        values.push_back(v);
        mask.push_back(low <= v && v <= high);
      }
  test::volume_files::write_file(dir / "hu.raw", "", test::sample_bytes_of(values));
  test::volume_files::write_file(dir / "mask.raw", "", mask);
}

const std::string kRaw = " --raw 20x18x14:i16le ";

TEST(TissueCli, ThresholdPresetsAreTheirHounsfieldThresholds) {
  ScratchDirectory dir;
  write_ct_series(dir, "CT");
  write_raw(dir, 0, 0);
  for (const auto& [tissue, threshold] : {std::pair<const char*, const char*>{"bone", "300"},
                                          {"skin", "-300"}}) {
    SCOPED_TRACE(tissue);
    const test::CommandResult run =
        run_mvox(std::string("extract series --tissue ") + tissue + " -o t.ply -q", dir.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    ASSERT_EQ(run_mvox("extract hu.raw" + kRaw + "-t " + threshold + " -o r.ply -q", dir.path())
                  .exit_code,
              0);
    EXPECT_TRUE(test::ply_body(dir / "t.ply") == test::ply_body(dir / "r.ply"));
    EXPECT_GT(test::ply_body(dir / "t.ply").size(), 100u);
  }
}

TEST(TissueCli, RangePresetsAreTheSurfaceOfTheVoxelsInTheirRange) {
  ScratchDirectory dir;
  write_ct_series(dir, "CT");
  for (const auto& [tissue, low, high] :
       {std::tuple<const char*, int, int>{"fat", -190, -30}, {"soft-tissue", -29, 150}}) {
    SCOPED_TRACE(tissue);
    write_raw(dir, low, high);
    const test::CommandResult run =
        run_mvox(std::string("extract series --tissue ") + tissue + " -o t.ply -q", dir.path());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    ASSERT_EQ(run_mvox("extract mask.raw --raw 20x18x14:u8 -t 1 -o m.ply -q", dir.path()).exit_code,
              0);
    EXPECT_TRUE(test::ply_body(dir / "t.ply") == test::ply_body(dir / "m.ply"));
    EXPECT_GT(test::ply_body(dir / "t.ply").size(), 100u);
  }
}

TEST(TissueCli, InputsNotKnownToBeHounsfieldUnitsAreRefusedUnlessHuIsGiven) {
  ScratchDirectory dir;
  write_ct_series(dir, "MR");
  write_raw(dir, 0, 0);
  expect_one_line_error(run_mvox("extract series --tissue bone -o t.ply", dir.path()),
                        "--tissue bone is a range of Hounsfield units, and the input is a DICOM "
                        "series of modality MR, not CT");
  expect_one_line_error(run_mvox("extract hu.raw" + kRaw + "--tissue fat -o t.ply", dir.path()),
                        "does not say its values are Hounsfield units; add --hu");
  EXPECT_FALSE(std::filesystem::exists(dir / "t.ply"));
  EXPECT_EQ(run_mvox("extract hu.raw" + kRaw + "--tissue fat --hu -o t.ply -q", dir.path()).exit_code,
            0);
  expect_one_line_error(run_mvox("extract hu.raw" + kRaw + "--tissue bone -t 5 -o t.ply", dir.path()),
                        "--tissue: give -t or --tissue, not both", 2);
  expect_one_line_error(run_mvox("extract hu.raw" + kRaw + "--tissue brain -o t.ply", dir.path()),
                        "--tissue", 2);
}

}  // namespace
}  // namespace mvox
