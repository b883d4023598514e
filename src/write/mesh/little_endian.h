#pragma once
// Little-endian stores, so binary PLY and STL files are the same on any host: on a
// little-endian host the value's own four bytes in one store, elsewhere by shifts. (GCC did not
// always merge the four shifted byte stores into one: in STL's triangle loop each float went out
// a byte at a time.)
#include <cstdint>
#include <cstring>

namespace mvox {

inline unsigned char* store_le32(unsigned char* out, std::uint32_t value) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  std::memcpy(out, &value, sizeof value);
#else
  out[0] = static_cast<unsigned char>(value);
  out[1] = static_cast<unsigned char>(value >> 8);
  out[2] = static_cast<unsigned char>(value >> 16);
  out[3] = static_cast<unsigned char>(value >> 24);
#endif
  return out + 4;
}

// An IEEE float's 4 bytes, least significant first.
inline unsigned char* store_le_float(unsigned char* out, float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return store_le32(out, bits);
}

// The float whose 4 bytes, least significant first, are at `in`.
inline float load_le_float(const unsigned char* in) {
  std::uint32_t bits;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  std::memcpy(&bits, in, sizeof bits);
#else
  bits = std::uint32_t{in[0]} | std::uint32_t{in[1]} << 8 | std::uint32_t{in[2]} << 16 |
         std::uint32_t{in[3]} << 24;
#endif
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

}  // namespace mvox
