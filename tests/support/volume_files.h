#pragma once
// Test support for the NRRD and MetaImage readers: a volume size odd on every axis, files
// written from header text and sample bytes, every sample of the volume the factory opens,
// MetaImage header lines, and the axes and spacing a parsed header gives.
#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/input_format.h"
#include "read/raw/raw_format.h"
#include "volume_samples.h"

namespace mvox::test::volume_files {

// Odd, different sizes on every axis, so that a swapped axis cannot go unnoticed.
constexpr std::uint32_t kWidth = 13, kHeight = 11, kDepth = 9;
constexpr const char* kSizes = "13 11 9";

// Writes `text` then `bytes` to `path`; a failure fails the test.
void write_file(const std::string& path, const std::string& text,
                const std::vector<unsigned char>& bytes = {});

// Every sample of the volume the factory opens for `path` (no --raw).
template <typename T>
std::vector<T> read_volume(const std::string& path, VolumeInfo* info = nullptr) {
  auto source = open_slice_source({path}, std::nullopt);
  if (info) *info = source->info();
  return test::read_samples<T>(*source);
}

// "big" or "little".
const char* order_name(ByteOrder order);

// The lines of a MetaImage header of a kWidth x kHeight x kDepth volume of `element_type`, then
// `extra` (which must name the data: ElementDataFile comes last).
std::string metaimage_fields(const std::string& element_type, const std::string& extra);

// Expects the volume's axes (unit vectors) and spacing to be these.
void expect_axes(const VolumeInfo& info, const double (&axes)[3][3], const double (&spacing)[3]);

}  // namespace mvox::test::volume_files
