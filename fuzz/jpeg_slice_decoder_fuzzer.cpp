// Fuzzes the strict JPEG slice decoder (src/read/image_stack/jpeg_slice_decoder.h): mvox's libjpeg
// error manager, which turns every warning into an error, jumps out of libjpeg and destroys it.
//
// Input: the bytes of a JPEG file. Properties: the decoder either refuses in one printable line
// naming the file, or asks exactly once for a slice of the size the file's SOF segment
// declares, and fills it.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <vector>

#include "error.h"
#include "fuzz_check.h"
#include "read/image_stack/jpeg_slice_decoder.h"

namespace {

// Width and height from the first SOFn segment met walking the segments after SOI, or 0x0.
void declared_size(const std::uint8_t* data, std::size_t size, std::uint32_t* width,
                   std::uint32_t* height) {
  *width = *height = 0;
  std::size_t at = 2;
  while (at + 9 <= size && data[at] == 0xff) {
    const std::uint8_t code = data[at + 1];
    if (code >= 0xc0 && code <= 0xcf && code != 0xc4 && code != 0xc8 && code != 0xcc) {
      *height = std::uint32_t{data[at + 5]} << 8 | data[at + 6];
      *width = std::uint32_t{data[at + 7]} << 8 | data[at + 8];
      return;
    }
    if (code == 0xff) {  // a fill byte before the marker
      at += 1;
      continue;
    }
    if (code == 0xd8 || code == 0x01 || (code >= 0xd0 && code <= 0xd7)) {  // no length
      at += 2;
      continue;
    }
    // libjpeg reads a length under 2 (which counts itself) as 2, with no warning.
    at += 2 + std::max<std::size_t>(std::size_t{data[at + 2]} << 8 | data[at + 3], 2);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "fuzzed.jpg";
  static std::vector<unsigned char> samples;
  int calls = 0;
  std::uint32_t width = 0, height = 0;
  try {
    mvox::decode_jpeg_slice(path, data, size, [&](std::uint32_t w, std::uint32_t h) {
      ++calls;
      width = w;
      height = h;
      // Past 64 MiB the decoder must turn the failure into its one line, as for a machine
      // without the memory; and libFuzzer's RSS limit stays out of the way.
      if (std::uint64_t{w} * h > (64u << 20)) throw std::bad_alloc();
      samples.assign(std::size_t{w} * h, 0xa5);
      return samples.data();
    });
  } catch (const mvox::Error& error) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(error.what()), error.what());
    MVOX_FUZZ_CHECK(error.subject() == path, error.what());
    MVOX_FUZZ_CHECK(calls <= 1, "the slice was asked for more than once");
    return 0;
  }
  MVOX_FUZZ_CHECK(calls == 1, "a decoded slice was never asked for");
  MVOX_FUZZ_CHECK(width > 0 && height > 0, "a slice without samples");
  std::uint32_t sof_width = 0, sof_height = 0;
  declared_size(data, size, &sof_width, &sof_height);
  MVOX_FUZZ_CHECK(sof_width == width && sof_height == height,
                  "slice " + std::to_string(width) + "x" + std::to_string(height) + ", header " +
                      std::to_string(sof_width) + "x" + std::to_string(sof_height));
  return 0;
}
