// Fuzzes the --raw spec parser (src/read/raw/raw_format.h) with arbitrary text. Properties: it
// either refuses with a one-line error naming --raw, or returns a format whose sizes are consistent
// and that reads back the same from its own text.
#include <cstddef>
#include <cstdint>
#include <string>

#include "error.h"
#include "fuzz_check.h"
#include "read/raw/raw_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string spec(reinterpret_cast<const char*>(data), size);
  mvox::RawFormat format;
  try {
    format = mvox::parse_raw_format(spec);
  } catch (const mvox::Error& e) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(e.what()), e.what());
    MVOX_FUZZ_CHECK(e.subject() == "--raw", e.what());
    return 0;
  }
  MVOX_FUZZ_CHECK(format.width >= 1 && format.height >= 1, spec);
  MVOX_FUZZ_CHECK(format.bytes_per_sample == mvox::sample_bytes(format.type), spec);
  // slice_bytes() and the volume's size fit (parse_raw_format promises it), computed exactly.
  const unsigned __int128 slice =
      static_cast<unsigned __int128>(format.width) * format.height * format.bytes_per_sample;
  MVOX_FUZZ_CHECK(slice == format.slice_bytes(), spec);
  MVOX_FUZZ_CHECK(slice * (format.depth == 0 ? 1 : format.depth) <= INT64_MAX, spec);
  // "WxH[xD] TYPE" back into "WxH[xD]:TYPE" gives the same format.
  std::string text = mvox::raw_format_text(format);
  text[text.find(' ')] = ':';
  const mvox::RawFormat again = mvox::parse_raw_format(text);
  MVOX_FUZZ_CHECK(again.width == format.width && again.height == format.height &&
                      again.depth == format.depth && again.type == format.type &&
                      (format.bytes_per_sample == 1 || again.byte_order == format.byte_order),
                  spec + " -> " + text);
  return 0;
}
