#include "read/image_stack/image_file_check.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace mvox {
namespace {

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// CRC-32 as PNG defines it (ISO 3309), which is zlib's crc32; zlib's own is table-driven and
// fast, so checking a slice costs a few percent of decoding it.
std::uint32_t png_crc(const unsigned char* bytes, std::size_t size) {
  std::uint32_t crc = static_cast<std::uint32_t>(::crc32(0L, Z_NULL, 0));
  // zlib takes a uInt length: feed very large chunks in pieces.
  while (size > 0) {
    const uInt piece = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, bytes, piece));
    bytes += piece;
    size -= piece;
  }
  return crc;
}

std::uint32_t load_big_endian(const unsigned char* bytes) {
  return std::uint32_t{bytes[0]} << 24 | std::uint32_t{bytes[1]} << 16 |
         std::uint32_t{bytes[2]} << 8 | std::uint32_t{bytes[3]};
}

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
    const std::uint32_t length = load_big_endian(bytes + at);
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
    const std::uint32_t stored = load_big_endian(type + 4 + length);
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
  if (size >= sizeof kPngSignature && std::memcmp(bytes, kPngSignature, sizeof kPngSignature) == 0)
    return png_problem(bytes, size);
  if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff)
    return jpeg_problem(bytes, size);
  return "";
}

}  // namespace mvox
