#include "image_file_check.h"

#include <array>
#include <cstdint>
#include <cstring>

namespace mvox {
namespace {

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// CRC-32 as PNG defines it (ISO 3309, polynomial 0xEDB88320 reflected), sliced by eight:
// eight tables let the loop take eight bytes per step, so checking a slice costs a few
// percent of decoding it (Intel's slicing-by-8, Kounavis and Berry, 2005).
using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;

constexpr CrcTables make_crc_tables() {
  CrcTables tables{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    tables[0][n] = c;
  }
  for (std::uint32_t n = 0; n < 256; ++n)
    for (int t = 1; t < 8; ++t)
      tables[t][n] = (tables[t - 1][n] >> 8) ^ tables[0][tables[t - 1][n] & 0xff];
  return tables;
}

constexpr CrcTables kCrcTables = make_crc_tables();

std::uint32_t crc32(const unsigned char* bytes, std::size_t size) {
  std::uint32_t c = 0xffffffffu;
  const auto& t = kCrcTables;
  for (; size >= 8; size -= 8, bytes += 8) {
    // Byte by byte into two words: no unaligned loads, the same on any byte order.
    const std::uint32_t low = c ^ (std::uint32_t{bytes[0]} | std::uint32_t{bytes[1]} << 8 |
                                   std::uint32_t{bytes[2]} << 16 | std::uint32_t{bytes[3]} << 24);
    c = t[7][low & 0xff] ^ t[6][(low >> 8) & 0xff] ^ t[5][(low >> 16) & 0xff] ^ t[4][low >> 24] ^
        t[3][bytes[4]] ^ t[2][bytes[5]] ^ t[1][bytes[6]] ^ t[0][bytes[7]];
  }
  for (; size > 0; --size, ++bytes) c = t[0][(c ^ *bytes) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
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
    if (crc32(type, 4 + std::size_t{length}) != stored)
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
