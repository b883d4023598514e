#pragma once
// Little-endian stores by shifts, so binary PLY and STL files are the same on any host.
#include <cstdint>
#include <cstring>

namespace mvox {

inline unsigned char* store_le32(unsigned char* out, std::uint32_t value) {
  out[0] = static_cast<unsigned char>(value);
  out[1] = static_cast<unsigned char>(value >> 8);
  out[2] = static_cast<unsigned char>(value >> 16);
  out[3] = static_cast<unsigned char>(value >> 24);
  return out + 4;
}

// An IEEE float's 4 bytes, least significant first.
inline unsigned char* store_le_float(unsigned char* out, float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return store_le32(out, bits);
}

}  // namespace mvox
