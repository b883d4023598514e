#pragma once
// One slice of a volume as the engine reads it: a borrowed 2-D array of samples.
#include <cstddef>
#include <cstdint>

namespace mvox {

// Sample types the engine classifies, always in the host's native byte order (readers swap).
enum class SampleType : std::uint8_t { u8, u16, i16, f32 };

constexpr std::size_t sample_bytes(SampleType type) {
  return type == SampleType::u8 ? 1 : type == SampleType::f32 ? 4 : 2;
}

const char* sample_type_name(SampleType type);  // "u8", "u16", "i16", "f32"

// A borrowed view of width x height samples, row y starting at
// `static_cast<const char*>(samples) + y * row_stride_bytes`.
// `samples` must stay valid until the call that receives the view returns. Neither `samples`
// nor `row_stride_bytes` need be aligned: the engine loads samples byte-wise.
struct SliceView {
  const void* samples = nullptr;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::size_t row_stride_bytes = 0;  // >= width * sample_bytes(type)
  SampleType type = SampleType::u8;
};

}  // namespace mvox
