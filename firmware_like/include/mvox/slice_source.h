#pragma once
// The interface every slice producer implements: file readers (src/) and the simulated scanner
// (sim/). A source hands out slices one at a time, in increasing z, holding only what it needs.
#include <cstdint>

#include "mvox/slice.h"

namespace mvox {

struct VolumeInfo {
  std::uint32_t width = 0;   // samples per row (x)
  std::uint32_t height = 0;  // rows per slice (y)
  std::uint32_t depth = 0;   // number of slices (z)
  SampleType type = SampleType::u8;
  double spacing[3] = {1, 1, 1};  // voxel size along x, y, z (mm or any unit)
  double origin[3] = {0, 0, 0};   // position of voxel (0,0,0)
  // World direction of each voxel axis, unit vectors: axes[0] is where increasing x (column)
  // points, axes[1] increasing y (row), axes[2] increasing z (slice). Identity unless the file
  // says otherwise (DICOM orientation, NRRD space directions, MetaImage TransformMatrix).
  // World position of voxel v = origin + sum over a of axes[a] * spacing[a] * v[a].
  double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
};

class SliceSource {
 public:
  virtual ~SliceSource() = default;
  virtual const VolumeInfo& info() const = 0;
  // Fills `slice` with the next slice and returns true, or returns false after the last one.
  // The view stays valid until the next call. Host readers throw on read errors; the core
  // never calls this (only sim/ and src/ drive sources), so that is safe.
  virtual bool next_slice(SliceView* slice) = 0;
  // The most memory, in bytes, the source holds at once while it streams (its slice buffer and
  // any decoder buffers), known once it is open and before its first slice: the reader's line of
  // a run's memory plan. Sources that cannot tell return 0. Must not allocate or read.
  virtual std::uint64_t working_bytes() const { return 0; }
};

}  // namespace mvox
