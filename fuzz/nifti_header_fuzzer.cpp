// libFuzzer target for parse_nifti_header (src/read/nifti/nifti_header.h): any bytes must either
// parse or be refused with mvox::Error; anything else (a crash, another exception, a sanitizer
// report) is a bug. Seeds: fuzz/corpus/nifti_header_fuzzer/ (NIfTI-1 and NIfTI-2 headers in
// both byte orders, placed by voxel sizes, qform and sform, scaled).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "error.h"
#include "read/nifti/nifti_header.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const mvox::NiftiHeader header = mvox::parse_nifti_header(data, size, "fuzz.nii");
    // What the reader relies on: a volume it can address, samples after the header, and a
    // placement of finite, nonzero voxel sizes and unit axes.
    const mvox::VolumeInfo& info = header.volume.info;
    if (info.width == 0 || info.height == 0 || info.depth == 0 ||
        (header.single_file && header.vox_offset < header.header_bytes) ||
        header.header_bytes > size)
      __builtin_trap();
    for (int axis = 0; axis < 3; ++axis) {
      if (!(info.spacing[axis] > 0) || !std::isfinite(info.spacing[axis]) ||
          !std::isfinite(info.origin[axis]))
        __builtin_trap();
      const double length = std::hypot(info.axes[axis][0], info.axes[axis][1], info.axes[axis][2]);
      if (!(std::fabs(length - 1) < 1e-6)) __builtin_trap();
    }
  } catch (const mvox::Error& error) {
    // Refusals are one line of printable text whatever bytes the header held.
    for (const char* c = error.what(); *c != '\0'; ++c) {
      if (static_cast<unsigned char>(*c) < 0x20 || *c == 0x7f) __builtin_trap();
    }
  }
  return 0;
}
