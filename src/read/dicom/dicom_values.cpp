#include "read/dicom/dicom_values.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "mvox/assert.h"

namespace mvox {
namespace {

bool is_integer(double value) {
  return std::floor(value) == value && std::fabs(value) <= 2147483647.0;
}

// The stored values' range: [0, 2^bits - 1], or [-2^(bits-1), 2^(bits-1) - 1] when signed.
void stored_range(const DicomValueMapping& m, double* lowest, double* highest) {
  const double steps = std::ldexp(1.0, m.bits_stored);
  *lowest = m.is_signed ? -steps / 2 : 0;
  *highest = m.is_signed ? steps / 2 - 1 : steps - 1;
}

template <typename Out>
Out to_integer_sample(std::int64_t value) {
  // exact_sample_type chose Out to hold every value; clamping only guards against a caller that
  // did not ask it.
  const std::int64_t low = std::numeric_limits<Out>::min();
  const std::int64_t high = std::numeric_limits<Out>::max();
  return static_cast<Out>(std::min(std::max(value, low), high));
}

// The stored value of a decoded sample: only the low `bits_stored` bits count (the rest may
// hold overlay bits in old files), sign-extended from the top stored bit when signed.
class StoredBits {
 public:
  explicit StoredBits(const DicomValueMapping& m)
      : mask_((std::int64_t{1} << m.bits_stored) - 1),
        sign_(m.is_signed ? std::int64_t{1} << (m.bits_stored - 1) : 0) {}
  template <typename In>
  std::int64_t operator()(In sample) const {
    const std::int64_t bits = static_cast<std::int64_t>(sample) & mask_;
    return (bits ^ sign_) - sign_;
  }

 private:
  std::int64_t mask_;
  std::int64_t sign_;
};

template <typename In, typename Out>
void convert(const In* in, std::size_t count, const DicomValueMapping& m, Out* out) {
  const StoredBits stored(m);
  if constexpr (std::is_floating_point_v<Out>) {
    for (std::size_t i = 0; i < count; ++i)
      out[i] = static_cast<Out>(m.slope * static_cast<double>(stored(in[i])) + m.intercept);
  } else {
    // Integer slope and intercept: integer arithmetic is exact where doubles might round.
    const auto slope = static_cast<std::int64_t>(m.slope);
    const auto intercept = static_cast<std::int64_t>(m.intercept);
    for (std::size_t i = 0; i < count; ++i)
      out[i] = to_integer_sample<Out>(slope * stored(in[i]) + intercept);
  }
}

template <typename In>
void convert_to(const In* in, std::size_t count, const DicomValueMapping& m, SampleType type,
                void* destination) {
  switch (type) {
    case SampleType::u8: convert(in, count, m, static_cast<std::uint8_t*>(destination)); return;
    case SampleType::u16: convert(in, count, m, static_cast<std::uint16_t*>(destination)); return;
    case SampleType::i16: convert(in, count, m, static_cast<std::int16_t*>(destination)); return;
    case SampleType::f32: convert(in, count, m, static_cast<float*>(destination)); return;
  }
}

}  // namespace

SampleType exact_sample_type(const std::vector<DicomValueMapping>& mappings) {
  MVOX_ASSERT(!mappings.empty());
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -lowest;
  bool integers = true;
  for (const DicomValueMapping& m : mappings) {
    double low, high;
    stored_range(m, &low, &high);
    const double a = m.slope * low + m.intercept;
    const double b = m.slope * high + m.intercept;
    lowest = std::min({lowest, a, b});
    highest = std::max({highest, a, b});
    integers = integers && is_integer(m.slope) && is_integer(m.intercept);
  }
  if (!integers) return SampleType::f32;
  if (lowest >= 0 && highest <= 255) return SampleType::u8;
  if (lowest >= 0 && highest <= 65535) return SampleType::u16;
  if (lowest >= -32768 && highest <= 32767) return SampleType::i16;
  return SampleType::f32;
}

void rescale_samples(const void* decoded, std::size_t count, const DicomValueMapping& m,
                     SampleType type, void* destination) {
  switch (m.bits_allocated) {
    case 8:
      if (m.is_signed)
        convert_to(static_cast<const std::int8_t*>(decoded), count, m, type, destination);
      else
        convert_to(static_cast<const std::uint8_t*>(decoded), count, m, type, destination);
      return;
    case 16:
      if (m.is_signed)
        convert_to(static_cast<const std::int16_t*>(decoded), count, m, type, destination);
      else
        convert_to(static_cast<const std::uint16_t*>(decoded), count, m, type, destination);
      return;
    case 32:
      if (m.is_signed)
        convert_to(static_cast<const std::int32_t*>(decoded), count, m, type, destination);
      else
        convert_to(static_cast<const std::uint32_t*>(decoded), count, m, type, destination);
      return;
  }
  MVOX_ASSERT(false && "bits_allocated must be 8, 16 or 32");
}

}  // namespace mvox
