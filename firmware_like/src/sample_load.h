#pragma once
// Reading one sample of a known type from possibly unaligned bytes, as a float. memcpy is the
// defined way to load from an unaligned address; compilers turn it into a plain load.
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "mvox/slice.h"

namespace mvox {

template <SampleType kType>
struct SampleOf;
template <>
struct SampleOf<SampleType::u8> {
  using type = std::uint8_t;
};
template <>
struct SampleOf<SampleType::u16> {
  using type = std::uint16_t;
};
template <>
struct SampleOf<SampleType::i16> {
  using type = std::int16_t;
};
template <>
struct SampleOf<SampleType::f32> {
  using type = float;
};

template <SampleType kType>
inline float load_sample(const unsigned char* row, std::uint32_t x) {
  typename SampleOf<kType>::type value;
  std::memcpy(&value, row + std::size_t{x} * sizeof value, sizeof value);
  return static_cast<float>(value);
}

template <SampleType kType>
using SampleTypeTag = std::integral_constant<SampleType, kType>;

// Calls body(SampleTypeTag<T>{}) with the SampleType of `type` as a compile-time constant, so
// that a loop over samples is compiled once per type with no switch inside. In the body:
// `constexpr SampleType kType = decltype(tag)::value;`.
template <class Body>
inline auto dispatch_sample_type(SampleType type, Body&& body) {
  switch (type) {
    case SampleType::u8: return body(SampleTypeTag<SampleType::u8>{});
    case SampleType::u16: return body(SampleTypeTag<SampleType::u16>{});
    case SampleType::i16: return body(SampleTypeTag<SampleType::i16>{});
    default: return body(SampleTypeTag<SampleType::f32>{});
  }
}

}  // namespace mvox
