#include "read/tiff/tiff_predictor.h"

#include <cstring>

namespace mvox {
namespace {

// Samples are loaded and stored with memcpy: a strip may start at any byte of a buffer.
template <typename T>
T load(const unsigned char* at) {
  T value;
  std::memcpy(&value, at, sizeof value);
  return value;
}

template <typename T>
void store(unsigned char* at, T value) {
  std::memcpy(at, &value, sizeof value);
}

std::uint16_t swapped(std::uint16_t v) { return __builtin_bswap16(v); }
std::uint32_t swapped(std::uint32_t v) { return __builtin_bswap32(v); }

template <typename T>
void finish(unsigned char* samples, std::size_t rows, std::size_t row_samples, bool byte_swapped,
            bool horizontal) {
  const std::size_t count = rows * row_samples;
  if constexpr (sizeof(T) > 1) {
    if (byte_swapped) {
      for (std::size_t i = 0; i < count; ++i)
        store<T>(samples + i * sizeof(T), swapped(load<T>(samples + i * sizeof(T))));
    }
  }
  if (!horizontal) return;
  for (std::size_t row = 0; row < rows; ++row) {
    unsigned char* at = samples + row * row_samples * sizeof(T);
    T sum = row_samples > 0 ? load<T>(at) : T{0};
    for (std::size_t i = 1; i < row_samples; ++i) {
      sum = static_cast<T>(sum + load<T>(at + i * sizeof(T)));
      store<T>(at + i * sizeof(T), sum);
    }
  }
}

}  // namespace

bool finish_tiff_samples(unsigned char* samples, std::size_t rows, std::size_t row_samples,
                         std::size_t sample_bytes, bool byte_swapped, std::uint16_t predictor) {
  if (predictor != 1 && predictor != 2) return false;
  const bool horizontal = predictor == 2;
  switch (sample_bytes) {
    case 1: finish<std::uint8_t>(samples, rows, row_samples, byte_swapped, horizontal); return true;
    case 2:
      finish<std::uint16_t>(samples, rows, row_samples, byte_swapped, horizontal);
      return true;
    case 4:
      finish<std::uint32_t>(samples, rows, row_samples, byte_swapped, horizontal);
      return true;
    default: return false;
  }
}

void reverse_bit_order(unsigned char* bytes, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    unsigned b = bytes[i];
    b = ((b & 0xF0u) >> 4) | ((b & 0x0Fu) << 4);
    b = ((b & 0xCCu) >> 2) | ((b & 0x33u) << 2);
    b = ((b & 0xAAu) >> 1) | ((b & 0x55u) << 1);
    bytes[i] = static_cast<unsigned char>(b);
  }
}

}  // namespace mvox
