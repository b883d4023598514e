#pragma once
// DICOM stored values to modality values (Hounsfield units for CT): value = slope * stored +
// intercept (RescaleSlope, RescaleIntercept), into the smallest sample type that holds every
// value of the series exactly, so that a threshold means the same as in any DICOM viewer.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mvox/slice.h"

namespace mvox {

// How a slice's stored values are laid out and mapped.
struct DicomValueMapping {
  std::uint16_t bits_allocated = 16;  // 8, 16 or 32 bits per sample in the decoded buffer
  std::uint16_t bits_stored = 16;     // the values span 2^bits_stored steps
  bool is_signed = false;             // two's complement stored values
  double slope = 1;
  double intercept = 0;
};

// The first of u8, u16, i16 that holds slope * v + intercept for every stored value v that
// `bits_stored` and `is_signed` allow, in every mapping, when slopes and intercepts are all
// integers; otherwise f32 (exact for integers up to 2^24, the nearest float otherwise).
// E.g. 12-bit unsigned CT with intercept -1024: i16 (-1024 .. 3071); 12-bit unsigned MR without
// rescale: u16; 8-bit unsigned: u8; 16-bit signed with intercept -1024: f32 (-33792 .. 31743).
// `mappings` must not be empty.
SampleType exact_sample_type(const std::vector<DicomValueMapping>& mappings);

// Writes `count` modality values into `destination` as `type` (which must hold them, see
// exact_sample_type) from `decoded`, GDCM's decoded samples: `mapping.bits_allocated` wide,
// native byte order. Only the low `bits_stored` bits of a sample count (old files keep overlays
// in the others); signed values are sign-extended from the top stored bit.
void rescale_samples(const void* decoded, std::size_t count, const DicomValueMapping& mapping,
                     SampleType type, void* destination);

}  // namespace mvox
