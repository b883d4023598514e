#pragma once
// A slice source that evaluates a sim/ phantom voxel by voxel into a buffer the caller owns: the
// simulated scanner's job (sim/simulated_scanner.h) without its heap. SimulatedScanner allocates
// its slice buffer with std::vector and reports bad options by throwing, neither of which the
// board has; this source takes a static buffer instead and handles 8-bit samples only.
//
// Samples are what SimulatedScanner records with default_scan_options(SampleType::u8),
// partial_volume = true and no point-spread blur: round(255 * partial_volume_density), clamped
// to 0 .. 255 (sim::sample_value).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "mvox/slice_source.h"
#include "phantom.h"

namespace mvox::firmware {

class PhantomSlices final : public SliceSource {
 public:
  // `phantom` and `buffer` are borrowed; `buffer` must hold width * height bytes of the
  // phantom's grid (fits() tells).
  PhantomSlices(const sim::Phantom& phantom, std::uint8_t* buffer, std::size_t buffer_bytes)
      : phantom_(phantom), buffer_(buffer), buffer_bytes_(buffer_bytes) {
    const sim::Grid grid = phantom.grid();
    info_.width = grid.width;
    info_.height = grid.height;
    info_.depth = grid.depth;
    info_.type = SampleType::u8;
  }

  bool fits() const { return std::size_t{info_.width} * info_.height <= buffer_bytes_; }

  const VolumeInfo& info() const override { return info_; }

  bool next_slice(SliceView* slice) override {
    if (next_z_ >= info_.depth || !fits()) return false;
    std::uint8_t* out = buffer_;
    for (std::uint32_t y = 0; y < info_.height; ++y)
      for (std::uint32_t x = 0; x < info_.width; ++x)
        *out++ = sample(phantom_.partial_volume_density(x, y, next_z_, 0.0));
    ++next_z_;
    slice->samples = buffer_;
    slice->width = info_.width;
    slice->height = info_.height;
    slice->row_stride_bytes = info_.width;
    slice->type = SampleType::u8;
    return true;
  }

  std::uint64_t working_bytes() const override { return std::size_t{info_.width} * info_.height; }

  // sim::sample_value() for default_scan_options(SampleType::u8): offset 0, scale 255.
  static std::uint8_t sample(float density) {
    const double value = 255.0 * density;
    if (!(value > 0.0)) return 0;  // NaN too
    if (value > 255.0) return 255;
    return static_cast<std::uint8_t>(std::round(value));
  }

 private:
  const sim::Phantom& phantom_;
  std::uint8_t* buffer_;
  std::size_t buffer_bytes_;
  VolumeInfo info_;
  std::uint32_t next_z_ = 0;
};

}  // namespace mvox::firmware
