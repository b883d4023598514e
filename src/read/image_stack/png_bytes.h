#pragma once
// PNG's byte layout, for the readers that look inside PNG files (image_header.cpp,
// image_file_check.cpp, png_slice_decoder.cpp, png_plain_decoder.cpp): the signature, the
// big-endian numbers of chunk headers and IHDR, and the CRC-32 of a chunk's type and data.
#include <zlib.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace mvox {

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

inline bool has_png_signature(const unsigned char* bytes, std::size_t size) {
  return size >= sizeof kPngSignature &&
         std::memcmp(bytes, kPngSignature, sizeof kPngSignature) == 0;
}

// A chunk's length, IHDR's width and height: 4 bytes, most significant first.
inline std::uint32_t png_uint32(const unsigned char* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3];
}

// CRC-32 as PNG defines it (ISO 3309), which is zlib's crc32, over `size` bytes (a chunk's type
// and data).
inline std::uint32_t png_crc(const unsigned char* bytes, std::size_t size) {
  std::uint32_t crc = static_cast<std::uint32_t>(::crc32(0L, Z_NULL, 0));
  // zlib takes a uInt length: very large chunks go in pieces.
  while (size > 0) {
    const uInt piece = static_cast<uInt>(std::min<std::size_t>(size, std::size_t{1} << 30));
    crc = static_cast<std::uint32_t>(::crc32(crc, bytes, piece));
    bytes += piece;
    size -= piece;
  }
  return crc;
}

}  // namespace mvox
