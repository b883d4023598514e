// The real DICOM files in ../shared/datasets (skipped, with the reason, when absent): two
// series' size, spacing, slice order and values, checked against GDCM's own reading of the
// positions, and single files that agree across encodings.
#include <gdcmAttribute.h>
#include <gdcmReader.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "dicom_series.h"
#include "read/dicom/dicom_series_source.h"

namespace mvox {
namespace {

namespace fs = std::filesystem;
using test::dicom_series::cross;
using test::dicom_series::dataset;
using test::dicom_series::dot;
using test::dicom_series::open_series;
using test::dicom_series::read_values;
using test::dicom_series::Vec3;

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
