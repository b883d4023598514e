#pragma once
// What a volume file's header says about its samples (NRRD, MetaImage, NIfTI): sizes, the sample type
// as stored, byte order, compression, and the geometry the engine's VolumeInfo carries. Filled
// by the header parsers, read by StoredVolumeSource.
#include <cstdint>
#include <string>

#include "mvox/slice_source.h"
#include "read/raw/raw_format.h"

namespace mvox {

// Sample types as stored in a file. The engine classifies u8, u16, i16 and f32; i8 is widened
// to i16 on reading, which keeps every value; i32, u32 and f64 become f32, exact for integers up
// to 2^24 in magnitude (label maps), the nearest float otherwise.
enum class StoredSample : std::uint8_t { u8, i8, u16, i16, f32, i32, u32, f64 };

enum class Compression : std::uint8_t {
  none,
  gzip,  // NRRD "encoding: gzip"
  zlib,  // MetaImage "CompressedData = True"
};

struct StoredVolume {
  // width, height, depth, the engine's sample type (engine_sample_type(stored)), spacing,
  // origin and axes.
  VolumeInfo info;
  StoredSample stored = StoredSample::u8;
  ByteOrder byte_order = ByteOrder::little;  // of the stored samples; u8 and i8 are order-free
  Compression compression = Compression::none;
  // Samples are scale_slope * stored + scale_intercept (NIfTI's scl_slope and scl_inter); when
  // that is not the identity, info.type is f32 (scaled_engine_type).
  double scale_slope = 1;
  double scale_intercept = 0;
  bool scaled() const { return scale_slope != 1 || scale_intercept != 0; }
};

std::size_t stored_sample_bytes(StoredSample sample);
SampleType engine_sample_type(StoredSample sample);
// The engine's type for `volume`: f32 when it is scaled, else engine_sample_type(stored).
SampleType scaled_engine_type(const StoredVolume& volume);
const char* stored_sample_name(StoredSample sample);  // "u8", "i8", "u16", "i16", "f32", ...

// Bytes one slice, and the whole volume, take in the file (before any decompression).
std::uint64_t stored_slice_bytes(const StoredVolume& volume);
std::uint64_t stored_volume_bytes(const StoredVolume& volume);

// "103x94x161 u8", for messages.
std::string stored_volume_text(const StoredVolume& volume);

// True when a width x height x depth volume of `sample_bytes`-byte samples, and one slice of it
// widened to the engine's type, stay below 2^63 bytes (a signed 64-bit file offset), so that
// no size or offset computed from it can overflow. Every dimension must be at least 1 and fit
// in 32 bits.
bool volume_size_fits(std::uint64_t width, std::uint64_t height, std::uint64_t depth,
                      std::size_t sample_bytes);

// Sets spacing[axis] and axes[axis] from a direction vector whose length is the voxel size
// along that axis (NRRD "space directions"; a negative spacing is a direction -1 * unit axis).
// Returns false when the vector has zero or subnormal length or a component that is not finite.
bool set_axis_from_vector(VolumeInfo& info, int axis, const double vector[3]);

// For a header that states only two axes (a single slice), the third axis is the unit normal of
// the first two (right-handed), spacing 1. Returns false when the first two are parallel.
bool complete_third_axis(VolumeInfo& info);

}  // namespace mvox
