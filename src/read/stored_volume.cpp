#include "read/stored_volume.h"

#include <cmath>
#include <limits>

namespace mvox {

std::size_t stored_sample_bytes(StoredSample sample) {
  switch (sample) {
    case StoredSample::u8:
    case StoredSample::i8: return 1;
    case StoredSample::u16:
    case StoredSample::i16: return 2;
    case StoredSample::f32:
    case StoredSample::i32:
    case StoredSample::u32: return 4;
    case StoredSample::f64: return 8;
  }
  return 1;
}

SampleType engine_sample_type(StoredSample sample) {
  switch (sample) {
    case StoredSample::u8: return SampleType::u8;
    case StoredSample::i8:
    case StoredSample::i16: return SampleType::i16;
    case StoredSample::u16: return SampleType::u16;
    case StoredSample::f32:
    case StoredSample::i32:
    case StoredSample::u32:
    case StoredSample::f64: return SampleType::f32;
  }
  return SampleType::u8;
}

SampleType scaled_engine_type(const StoredVolume& volume) {
  return volume.scaled() ? SampleType::f32 : engine_sample_type(volume.stored);
}

const char* stored_sample_name(StoredSample sample) {
  switch (sample) {
    case StoredSample::u8: return "u8";
    case StoredSample::i8: return "i8";
    case StoredSample::u16: return "u16";
    case StoredSample::i16: return "i16";
    case StoredSample::f32: return "f32";
    case StoredSample::i32: return "i32";
    case StoredSample::u32: return "u32";
    case StoredSample::f64: return "f64";
  }
  return "?";
}

std::uint64_t stored_slice_bytes(const StoredVolume& volume) {
  return std::uint64_t{volume.info.width} * volume.info.height * stored_sample_bytes(volume.stored);
}

std::uint64_t stored_volume_bytes(const StoredVolume& volume) {
  return stored_slice_bytes(volume) * volume.info.depth;
}

std::string stored_volume_text(const StoredVolume& volume) {
  return std::to_string(volume.info.width) + "x" + std::to_string(volume.info.height) + "x" +
         std::to_string(volume.info.depth) + " " + stored_sample_name(volume.stored);
}

bool volume_size_fits(std::uint64_t width, std::uint64_t height, std::uint64_t depth,
                      std::size_t sample_bytes) {
  constexpr std::uint64_t kMaxDimension = std::numeric_limits<std::uint32_t>::max();
  if (width == 0 || height == 0 || depth == 0) return false;
  if (width > kMaxDimension || height > kMaxDimension || depth > kMaxDimension) return false;
  // Widened samples take up to 4 bytes, whatever the stored size, so check with that too.
  const std::uint64_t bytes = sample_bytes < 4 ? 4 : sample_bytes;
  const std::uint64_t limit = std::numeric_limits<std::int64_t>::max();
  const std::uint64_t row = width * bytes;  // < 2^34, no overflow
  if (row > limit / height) return false;
  return row * height <= limit / depth;
}

bool set_axis_from_vector(VolumeInfo& info, int axis, const double vector[3]) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(vector[i])) return false;
  // hypot, not the root of the summed squares: those overflow for a component past 1e154, and a
  // spacing of 1e300 must reach WorldTransform::check, which calls it too large, rather than
  // be taken for no spacing at all.
  const double length = std::hypot(vector[0], vector[1], vector[2]);
  // A subnormal length keeps too few bits for the quotients to make a unit vector: no
  // direction either (found by nifti_header_fuzzer: NIfTI-2 sform columns of 1e-320).
  if (!(length >= std::numeric_limits<double>::min()) || !std::isfinite(length)) return false;
  info.spacing[axis] = length;
  for (int i = 0; i < 3; ++i) info.axes[axis][i] = vector[i] / length;
  return true;
}

bool complete_third_axis(VolumeInfo& info) {
  const double* a = info.axes[0];
  const double* b = info.axes[1];
  const double normal[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                            a[0] * b[1] - a[1] * b[0]};
  if (!set_axis_from_vector(info, 2, normal)) return false;
  info.spacing[2] = 1;
  return true;
}

}  // namespace mvox
