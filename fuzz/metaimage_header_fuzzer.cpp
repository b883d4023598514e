// libFuzzer target for parse_metaimage_header (src/read/metaimage/metaimage_header.h): any bytes
// must either parse or be refused with mvox::Error; anything else (a crash, another exception, a
// sanitizer report) is a bug. Seeds: fuzz/corpus/metaimage_header_fuzzer/.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "error.h"
#include "read/metaimage/metaimage_header.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const mvox::MetaImageHeader header = mvox::parse_metaimage_header(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.mha");
    // What the reader relies on: a header that parses describes a volume it can address.
    if (header.volume.info.width == 0 || header.volume.info.height == 0 ||
        header.volume.info.depth == 0 || header.header_bytes > size ||
        (!header.data_local && header.data_file.empty())) {
      __builtin_trap();
    }
  } catch (const mvox::Error& error) {
    // Refusals are one line of printable text whatever bytes the header held, because they end
    // up as "mvox: error: ..." on a terminal.
    for (const char* c = error.what(); *c != '\0'; ++c) {
      if (static_cast<unsigned char>(*c) < 0x20 || *c == 0x7f) __builtin_trap();
    }
  }
  return 0;
}
