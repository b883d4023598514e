#include "read/image_stack/image_file_check.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "read/image_stack/png_bytes.h"

namespace mvox {
namespace {

// The chunk type for messages: four letters, anything else shown as '?'.
std::string chunk_name(const unsigned char* type) {
  std::string name;
  for (int i = 0; i < 4; ++i) {
    const unsigned char c = type[i];
    name += ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z')) ? static_cast<char>(c) : '?';
  }
  return name;
}

std::string png_problem(const unsigned char* bytes, std::size_t size) {
  std::size_t at = sizeof kPngSignature;
  bool first = true;
  for (;;) {
    if (size - at < 12) {
      const std::string where = size == at
                                    ? (first ? " before the IHDR chunk" : " before the IEND chunk")
                                    : " inside the chunk header at byte " + std::to_string(at);
      return "truncated PNG: the file ends at byte " + std::to_string(size) + where;
    }
    const std::uint32_t length = png_uint32(bytes + at);
    const unsigned char* type = bytes + at + 4;
    const std::string name = chunk_name(type);
    // PNG limits chunk lengths to 2^31 - 1.
    if (length > 0x7fffffffu)
      return "corrupt PNG: chunk at byte " + std::to_string(at) + " claims " +
             std::to_string(length) + " bytes";
    if (first && (name != "IHDR" || length != 13))
      return "corrupt PNG: the first chunk is not a 13-byte IHDR";
    if (length > size - at - 12) {
      return "truncated PNG: the file ends at byte " + std::to_string(size) + " inside the " +
             name + " chunk at byte " + std::to_string(at);
    }
    // The CRC covers the type and the data.
    const std::uint32_t stored = png_uint32(type + 4 + length);
    if (png_crc(type, 4 + std::size_t{length}) != stored)
      return "corrupt PNG: the " + name + " chunk at byte " + std::to_string(at) +
             " fails its CRC check";
    if (name == "IEND") return "";
    at += 12 + std::size_t{length};
    first = false;
  }
}

std::string jpeg_problem(const unsigned char* bytes, std::size_t size) {
  std::size_t end = size;
  while (end > 3 && bytes[end - 1] == 0) --end;
  if (end < 4 || bytes[end - 2] != 0xff || bytes[end - 1] != 0xd9)
    return "truncated JPEG: the file does not end with the end-of-image marker (FF D9)";
  return "";
}

}  // namespace

std::string image_file_problem(const unsigned char* bytes, std::size_t size) {
  if (has_png_signature(bytes, size)) return png_problem(bytes, size);
  if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff)
    return jpeg_problem(bytes, size);
  return "";
}

}  // namespace mvox
