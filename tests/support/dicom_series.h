#pragma once
// Test support for the DICOM reader's tests: series written with dicom_writer.h in a pattern
// that shows any axis swap, flip or wrong slice order, every sample a source delivers, a series
// opened from a folder, refusals checked by subject and problem, and the shared datasets.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "dicom_writer.h"
#include "mvox/slice_source.h"
#include "read/dicom/dicom_series_source.h"

namespace mvox::test::dicom_series {

using Vec3 = std::array<double, 3>;

Vec3 cross(const Vec3& a, const Vec3& b);
double dot(const Vec3& a, const Vec3& b);

// Every sample of every slice, x fastest, then y, then z, as the engine would see it.
std::vector<double> read_values(SliceSource& source);

// The DICOM series in `directory` (its files in name order), notes collected in `notes`.
DicomSeriesSource open_series(const std::string& directory,
                              std::vector<std::string>* notes = nullptr,
                              const std::string& series_uid = "");

// Runs `action`, which must throw mvox::Error about `subject` whose problem mentions `words`.
void expect_error(const std::function<void()>& action, const std::string& subject,
                  const std::string& words);

// A slice's stored values: a pattern that differs in every slice, row and column, so that an
// axis swap, a flip or a wrong slice order shows.
std::vector<std::int64_t> pattern(std::uint32_t width, std::uint32_t height, std::int64_t slice,
                                  std::int64_t base = 0);

// `count` slices stacked along the normal of `spec.orientation` (axial without one), `gap` mm
// apart from `origin`, stored values pattern(k) for the slice at position k. Files are named
// "<prefix><i>.dcm" with i = position_of_file order: file i holds the slice at position
// order[i] (identity when empty).
void write_series(const std::string& directory, const std::string& prefix, DicomSliceSpec spec,
                  int count, const Vec3& origin, double gap, std::vector<int> order = {});

// `name` in ../shared/datasets.
std::string dataset(const std::string& name);

}  // namespace mvox::test::dicom_series

// Skips the test, saying why, when the shared dataset `name` is absent.
#define MVOX_REQUIRE_DATASET(name)                                         \
  if (!std::filesystem::exists(::mvox::test::dicom_series::dataset(name))) \
  GTEST_SKIP() << ::mvox::test::dicom_series::dataset(name)                \
               << " is absent (../shared/datasets is not beside the checkout)"
