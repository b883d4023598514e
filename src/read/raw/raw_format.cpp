#include "read/raw/raw_format.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "error.h"

namespace mvox {
namespace {

constexpr const char* kSubject = "--raw";
constexpr const char* kTypeList = "u8, u16le, u16be, i16le, i16be, f32le";

struct RawType {
  const char* name;
  SampleType type;
  ByteOrder order;
};

constexpr RawType kRawTypes[] = {
    {"u8", SampleType::u8, ByteOrder::little},  {"u16le", SampleType::u16, ByteOrder::little},
    {"u16be", SampleType::u16, ByteOrder::big}, {"i16le", SampleType::i16, ByteOrder::little},
    {"i16be", SampleType::i16, ByteOrder::big}, {"f32le", SampleType::f32, ByteOrder::little},
};

// User text as it goes into a message: control characters (a newline would start a second
// line) shown as '?', and long text cut short.
std::string printable(const std::string& text) {
  constexpr std::size_t kShownChars = 60;
  std::string shown;
  for (std::size_t i = 0; i < text.size() && i < kShownChars; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    shown += (c < 0x20 || c == 0x7f) ? '?' : static_cast<char>(c);
  }
  if (text.size() > kShownChars) shown += "...";
  return shown;
}

[[noreturn]] void fail(const std::string& spec, const std::string& problem) {
  throw Error(kSubject, "\"" + printable(spec) + "\": " + problem);
}

[[noreturn]] void fail_syntax(const std::string& spec) {
  fail(spec, std::string("expected WxH:TYPE (one file per slice) or WxHxD:TYPE (one volume "
                         "file), TYPE one of ") +
                 kTypeList);
}

// Parses one dimension: decimal digits only (no sign, no spaces), 1 .. 2^32-1.
std::uint32_t parse_dimension(const std::string& spec, const std::string& text, const char* axis) {
  if (text.empty()) fail(spec, std::string("missing ") + axis);
  if (!std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    fail(spec, std::string(axis) + " \"" + printable(text) + "\" is not a whole number");
  }
  std::uint64_t value = 0;
  for (char c : text) {
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
    // Checked per digit so a long run of digits cannot wrap around.
    if (value > std::numeric_limits<std::uint32_t>::max()) {
      fail(spec, std::string(axis) + " " + printable(text) + " is too large");
    }
  }
  if (value == 0) fail(spec, std::string(axis) + " must be at least 1");
  return static_cast<std::uint32_t>(value);
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = text.find(separator, start);
    parts.push_back(text.substr(start, end - start));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

}  // namespace

ByteOrder native_byte_order() {
  // C++17 has no std::endian; looking at the first byte of a known integer is portable, and
  // compilers fold it to a constant.
  const std::uint16_t probe = 1;
  unsigned char first_byte = 0;
  std::memcpy(&first_byte, &probe, 1);
  return first_byte == 1 ? ByteOrder::little : ByteOrder::big;
}

std::size_t RawFormat::slice_bytes() const {
  return static_cast<std::size_t>(width) * height * bytes_per_sample;
}

RawFormat parse_raw_format(const std::string& spec) {
  const std::vector<std::string> halves = split(spec, ':');
  if (halves.size() != 2) fail_syntax(spec);
  const std::vector<std::string> dims = split(halves[0], 'x');
  if (dims.size() < 2 || dims.size() > 3) fail_syntax(spec);

  RawFormat format;
  format.width = parse_dimension(spec, dims[0], "width");
  format.height = parse_dimension(spec, dims[1], "height");
  if (dims.size() == 3) format.depth = parse_dimension(spec, dims[2], "depth");

  const std::string& type_name = halves[1];
  const RawType* found = std::find_if(std::begin(kRawTypes), std::end(kRawTypes),
                                      [&](const RawType& t) { return type_name == t.name; });
  if (found == std::end(kRawTypes)) {
    fail(spec,
         "unknown sample type \"" + printable(type_name) + "\", expected one of " + kTypeList);
  }
  format.type = found->type;
  format.byte_order = found->order;
  format.bytes_per_sample = sample_bytes(found->type);

  // Volume files are addressed with signed 64-bit offsets (fseeko, std::streamoff); keeping the
  // whole volume below that limit also keeps every slice size within std::size_t on 64-bit hosts.
  const std::uint64_t limit = std::min<std::uint64_t>(std::numeric_limits<std::int64_t>::max(),
                                                      std::numeric_limits<std::size_t>::max());
  const std::uint64_t row_bytes = std::uint64_t{format.width} * format.bytes_per_sample;
  const std::uint64_t slices = format.depth == 0 ? 1 : format.depth;
  if (row_bytes > limit / format.height || row_bytes * format.height > limit / slices) {
    fail(spec, "volume size overflows a 64-bit file offset");
  }
  return format;
}

std::string raw_format_text(const RawFormat& format) {
  std::string text = std::to_string(format.width) + "x" + std::to_string(format.height);
  if (format.depth != 0) text += "x" + std::to_string(format.depth);
  for (const RawType& t : kRawTypes) {
    if (t.type == format.type && (t.type == SampleType::u8 || t.order == format.byte_order)) {
      return text + " " + t.name;
    }
  }
  return text + " " + sample_type_name(format.type);
}

void swap_to_native(void* samples, std::size_t sample_count, std::size_t bytes_per_sample,
                    ByteOrder file_order) {
  if (bytes_per_sample < 2 || file_order == native_byte_order()) return;
  auto* bytes = static_cast<unsigned char*>(samples);
  // Byte-wise reversal needs no alignment and no type punning; the fixed-size cases let the
  // compiler vectorise the common 16- and 32-bit slices.
  switch (bytes_per_sample) {
    case 2:
      for (std::size_t i = 0; i < sample_count; ++i, bytes += 2) std::swap(bytes[0], bytes[1]);
      return;
    case 4:
      for (std::size_t i = 0; i < sample_count; ++i, bytes += 4) {
        std::swap(bytes[0], bytes[3]);
        std::swap(bytes[1], bytes[2]);
      }
      return;
    default:
      for (std::size_t i = 0; i < sample_count; ++i, bytes += bytes_per_sample) {
        std::reverse(bytes, bytes + bytes_per_sample);
      }
  }
}

SliceView native_slice_view(unsigned char* bytes, const RawFormat& format) {
  swap_to_native(bytes, format.slice_bytes() / format.bytes_per_sample, format.bytes_per_sample,
                 format.byte_order);
  SliceView slice;
  slice.samples = bytes;
  slice.width = format.width;
  slice.height = format.height;
  slice.row_stride_bytes = static_cast<std::size_t>(format.width) * format.bytes_per_sample;
  slice.type = format.type;
  return slice;
}

}  // namespace mvox
