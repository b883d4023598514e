#pragma once
// The --raw option: the layout of headerless slice files, and the byte swap that brings their
// samples into the host's order.
#include <cstddef>
#include <cstdint>
#include <string>

#include "mvox/slice.h"

namespace mvox {

enum class ByteOrder : std::uint8_t { little, big };

// Byte order of the machine running this code.
ByteOrder native_byte_order();

// A parsed --raw spec. Either one headerless file per slice (depth 0, "WxH:TYPE") or one
// headerless volume file holding `depth` slices back to back ("WxHxD:TYPE"). Rows are
// `width` samples with no padding; x varies fastest, then y, then z.
struct RawFormat {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t depth = 0;  // 0 = one file per slice
  SampleType type = SampleType::u8;
  ByteOrder byte_order = ByteOrder::little;  // of the file; u8 is order-free
  std::size_t bytes_per_sample = 1;

  // Bytes of one slice, width * height * bytes_per_sample; parse_raw_format guarantees that this
  // and depth * slice_bytes() fit in std::size_t and in a signed 64-bit file offset.
  std::size_t slice_bytes() const;
};

// Parses "WxH:TYPE" or "WxHxD:TYPE", TYPE one of u8, u16le, u16be, i16le, i16be, f32le.
// Throws mvox::Error with subject "--raw" saying what is wrong: a malformed spec, a zero or
// too large dimension, an unknown type (listing the valid ones), or a size that overflows.
RawFormat parse_raw_format(const std::string& spec);

// The spec back as text, e.g. "256x256 u16be" or "256x256x128 u8", for messages.
std::string raw_format_text(const RawFormat& format);

// Reverses the bytes of each of `sample_count` samples of `bytes_per_sample` bytes at `samples`
// when `file_order` differs from the native order; otherwise leaves them alone.
void swap_to_native(void* samples, std::size_t sample_count, std::size_t bytes_per_sample,
                    ByteOrder file_order);

// Swaps one slice read into `bytes` (format.slice_bytes() of them) to native order in place and
// returns the view of it the engine reads: the one step both raw readers finish every slice
// with.
SliceView native_slice_view(unsigned char* bytes, const RawFormat& format);

}  // namespace mvox
