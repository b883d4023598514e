#pragma once
// A slice source that "scans" a phantom: it hands the engine one slice at a time exactly as a
// file reader does, quantised to the chosen sample type, without ever holding the volume.
#include <cstdint>
#include <vector>

#include "mvox/slice_source.h"
#include "phantom.h"

namespace mvox::sim {

// How densities become samples: sample = offset + scale * density.
struct ScanOptions {
  SampleType type = SampleType::u8;
  double scale = 255;  // > 0, so that a higher density never gives a lower sample
  double offset = 0;
  double spacing[3] = {1, 1, 1};  // voxel size along x, y, z, > 0; copied to VolumeInfo
  double origin[3] = {0, 0, 0};   // position of voxel (0, 0, 0); copied to VolumeInfo
  // Record Phantom::partial_volume_density() instead of density(): edges blurred as in a real
  // scan, which gradient normals need to look smooth. Off by default: the exact-count tests
  // want the phantom's own voxels.
  bool partial_volume = false;
  // With partial_volume: a Gaussian point-spread function of this many voxels (>= 0) blurs the
  // one-voxel partial-volume ramp, as every scanner does; gradient normals need it to be free of
  // terrace rings where a surface runs almost along the voxel grid (mvox demo scans with 1).
  // 0: the ramp alone.
  double psf_sigma = 0;
};

// Options that use most of each type's range for densities in [0, 1]:
// u8 scale 255; u16 scale 4095 (12-bit, like most CT); i16 offset -1024, scale 3071 (air at
// -1024 as in Hounsfield units, density 1 at 2047); f32 scale 1 (samples are the densities).
ScanOptions default_scan_options(SampleType type);

// The sample value the scanner stores for `density`: offset + scale * density, and for the
// integer types rounded to nearest (halves away from zero) and clamped to the type's range.
// NaN gives the type's minimum for integer types.
double sample_value(double density, const ScanOptions& options);

// The sample threshold that matches `density_threshold` t, for the engine's "sample >= threshold
// is inner". f32: the sample of t, so density >= t implies sample >= threshold. Integer types:
// offset + scale * t rounded up and clamped, so that for a binary phantom (densities 0 and 1),
// 0 < t <= 1, an integer offset within the type's range and an integer scale, density >= t
// exactly when sample >= threshold. Other densities are quantised to steps of 1 / scale, so
// densities within one step of t may fall on either side.
double sample_threshold(double density_threshold, const ScanOptions& options);

class SimulatedScanner final : public SliceSource {
 public:
  // `phantom` is borrowed and must outlive the scanner. Allocates the one slice buffer
  // (width * height * sample_bytes(type) bytes) here and never again. Throws
  // std::invalid_argument when scale is not finite and > 0, offset is not finite, or a spacing
  // is not finite and > 0.
  explicit SimulatedScanner(const Phantom& phantom, const ScanOptions& options = {});

  const VolumeInfo& info() const override { return info_; }

  // Fills the buffer with slice z (0, 1, ... depth - 1 in turn) and points `slice` at it;
  // returns false, and keeps returning false, after the last slice. The view stays valid until
  // the next call (it always points at the same buffer) or the scanner's destruction.
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override { return slice_.size(); }

  // Starts again from slice 0.
  void rewind() { next_z_ = 0; }

 private:
  const Phantom* phantom_;
  ScanOptions options_;
  VolumeInfo info_;
  std::vector<unsigned char> slice_;  // one slice, rows packed (stride = width * sample bytes)
  std::uint32_t next_z_ = 0;
};

}  // namespace mvox::sim
