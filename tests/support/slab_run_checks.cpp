#include "slab_run_checks.h"

#include <gtest/gtest.h>

#include <vector>

#include "file_io.h"

namespace mvox::test {

const std::vector<MeshCase>& every_format_and_option() {
  static const std::vector<MeshCase> cases = {
      {"ply", ""},
      {"ply", "--ascii"},
      {"obj", ""},
      {"stl", ""},
      {"ply", "--triangulate"},
      {"ply", "--normals"},
      {"obj", "--normals --spacing 0.5,1,2 --origin -3,4,5"},
      {"ply", "--method cubes --normals --ascii"},
      {"ply", "--engine literal"},
      {"ply", "--surface paper-table1"},
      {"obj", "--interpolate --normals"},
  };
  return cases;
}

VolumeInfo u8_volume(std::uint32_t width, std::uint32_t height, std::uint32_t depth) {
  VolumeInfo volume;
  volume.width = width;
  volume.height = height;
  volume.depth = depth;
  volume.type = SampleType::u8;
  return volume;
}

std::vector<std::uint8_t> noise_samples(const VolumeInfo& volume, std::uint64_t seed) {
  return noise_samples(std::size_t{volume.width} * volume.height * volume.depth, seed);
}

std::vector<std::uint8_t> noise_samples(std::size_t voxels, std::uint64_t seed) {
  std::vector<std::uint8_t> bytes(voxels);
  std::uint64_t state = seed;
  for (std::uint8_t& byte : bytes) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    byte = static_cast<std::uint8_t>(state >> 56);
  }
  return bytes;
}

void write_noise(const std::string& path, std::uint32_t voxels, std::uint64_t seed) {
  write_bytes(path, noise_samples(voxels, seed));
}

std::string counters_of(const std::string& report) {
  const std::size_t from = report.find("\"inner_voxels\"");
  const std::size_t to = report.find("\"time_seconds\"");
  EXPECT_NE(from, std::string::npos) << report;
  EXPECT_NE(to, std::string::npos) << report;
  return from < to && to != std::string::npos ? report.substr(from, to - from) : "";
}

}  // namespace mvox::test
