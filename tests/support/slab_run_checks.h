#pragma once
// Test support for runs that must give one thread's bytes (slab threads, mvox-mpi ranks): noise
// volumes, whose surface crosses every slab boundary almost everywhere, and the counters of a
// --stats report, which must match while times and memory differ.
#include <cstdint>
#include <string>
#include <vector>

#include "mvox/slice_source.h"

namespace mvox::test {

// A mesh format (its extension) and `extract` options.
struct MeshCase {
  const char* extension;
  const char* options;
};
// Every format and the options that change what is written: what a run in slabs or ranks must
// write as one thread does.
const std::vector<MeshCase>& every_format_and_option();

// `voxels` bytes of 8-bit noise at `path`, the same for the same seed.
void write_noise(const std::string& path, std::uint32_t voxels, std::uint64_t seed);
// The same noise in memory.
std::vector<std::uint8_t> noise_samples(std::size_t voxels, std::uint64_t seed);
// An 8-bit volume of width x height x depth voxels, and its noise.
VolumeInfo u8_volume(std::uint32_t width, std::uint32_t height, std::uint32_t depth);
std::vector<std::uint8_t> noise_samples(const VolumeInfo& volume, std::uint64_t seed);

// The counters of a --stats report: from "inner_voxels" to the times (which, with the memory
// figures and the renderer's work counters after them, differ from run to run). Fails the test
// when the report has neither.
std::string counters_of(const std::string& report);

}  // namespace mvox::test
