#include "simulated_scanner.h"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace mvox::sim {
namespace {

template <typename T>
double clamp_round(double value) {
  constexpr double lo = std::numeric_limits<T>::lowest();
  constexpr double hi = std::numeric_limits<T>::max();
  // Negated comparison so that NaN lands on lo instead of an undefined integer conversion.
  if (!(value > lo)) return lo;
  if (value > hi) return hi;
  return std::round(value);
}

template <typename T>
double clamp_ceil(double value) {
  constexpr double lo = std::numeric_limits<T>::lowest();
  constexpr double hi = std::numeric_limits<T>::max();
  if (!(value > lo)) return lo;
  if (value > hi) return hi;
  return std::ceil(value);
}

// Writes one slice of samples of type T. memcpy per sample keeps the byte buffer free of
// type-punning questions; compilers turn it into a plain store.
template <typename T>
void fill_slice(const Phantom& phantom, std::uint32_t z, const ScanOptions& options,
                unsigned char* out) {
  const Grid grid = phantom.grid();
  for (std::uint32_t y = 0; y < grid.height; ++y) {
    for (std::uint32_t x = 0; x < grid.width; ++x) {
      const float density = options.partial_volume ? phantom.partial_volume_density(x, y, z, options.psf_sigma)
                                                   : phantom.density(x, y, z);
      const T sample = static_cast<T>(sample_value(density, options));
      std::memcpy(out, &sample, sizeof(T));
      out += sizeof(T);
    }
  }
}

void check_positive(double value, const std::string& what) {
  if (!(value > 0) || !std::isfinite(value)) {
    throw std::invalid_argument("simulated scanner: " + what + " must be finite and > 0, got " +
                                std::to_string(value));
  }
}

}  // namespace

ScanOptions default_scan_options(SampleType type) {
  ScanOptions options;
  options.type = type;
  switch (type) {
    case SampleType::u8: options.scale = 255; break;
    case SampleType::u16: options.scale = 4095; break;
    case SampleType::i16:
      options.offset = -1024;
      options.scale = 3071;
      break;
    case SampleType::f32: options.scale = 1; break;
  }
  return options;
}

double sample_value(double density, const ScanOptions& options) {
  const double value = options.offset + options.scale * density;
  switch (options.type) {
    case SampleType::u8: return clamp_round<std::uint8_t>(value);
    case SampleType::u16: return clamp_round<std::uint16_t>(value);
    case SampleType::i16: return clamp_round<std::int16_t>(value);
    case SampleType::f32: return static_cast<float>(value);
  }
  return value;
}

double sample_threshold(double density_threshold, const ScanOptions& options) {
  // Rounding up (not to nearest) keeps binary phantoms exact for every 0 < t <= 1: with integer
  // offset o and scale c, o < ceil(o + c t) <= o + c, i.e. above the sample of density 0 and
  // at most the sample of density 1. Rounding to nearest would let a small t fall back to o.
  const double value = options.offset + options.scale * density_threshold;
  switch (options.type) {
    case SampleType::u8: return clamp_ceil<std::uint8_t>(value);
    case SampleType::u16: return clamp_ceil<std::uint16_t>(value);
    case SampleType::i16: return clamp_ceil<std::int16_t>(value);
    case SampleType::f32: return static_cast<float>(value);
  }
  return value;
}

SimulatedScanner::SimulatedScanner(const Phantom& phantom, const ScanOptions& options)
    : phantom_(&phantom), options_(options) {
  check_positive(options.scale, "scale");
  if (!(options.psf_sigma >= 0) || !std::isfinite(options.psf_sigma))
    throw std::invalid_argument("simulated scanner: psf_sigma must be finite and >= 0, got " +
                                std::to_string(options.psf_sigma));
  if (!std::isfinite(options.offset)) {
    throw std::invalid_argument("simulated scanner: offset must be finite");
  }
  for (int axis = 0; axis < 3; ++axis) {
    check_positive(options.spacing[axis], std::string("spacing along ") + "xyz"[axis]);
  }
  const Grid grid = phantom.grid();
  info_.width = grid.width;
  info_.height = grid.height;
  info_.depth = grid.depth;
  info_.type = options.type;
  for (int axis = 0; axis < 3; ++axis) {
    info_.spacing[axis] = options.spacing[axis];
    info_.origin[axis] = options.origin[axis];
  }
  slice_.resize(std::size_t{grid.width} * grid.height * sample_bytes(options.type));
}

bool SimulatedScanner::next_slice(SliceView* slice) {
  if (next_z_ >= info_.depth) return false;
  unsigned char* out = slice_.data();
  switch (options_.type) {
    case SampleType::u8: fill_slice<std::uint8_t>(*phantom_, next_z_, options_, out); break;
    case SampleType::u16: fill_slice<std::uint16_t>(*phantom_, next_z_, options_, out); break;
    case SampleType::i16: fill_slice<std::int16_t>(*phantom_, next_z_, options_, out); break;
    case SampleType::f32: fill_slice<float>(*phantom_, next_z_, options_, out); break;
  }
  ++next_z_;
  slice->samples = slice_.data();
  slice->width = info_.width;
  slice->height = info_.height;
  slice->row_stride_bytes = std::size_t{info_.width} * sample_bytes(options_.type);
  slice->type = options_.type;
  return true;
}

}  // namespace mvox::sim
