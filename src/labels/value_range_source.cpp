#include "labels/value_range_source.h"

#include <cstring>
#include <utility>

namespace mvox {
namespace {

template <class T>
void mask_row(const unsigned char* row, std::uint32_t width, double low, double high,
              std::uint8_t* out) {
  for (std::uint32_t x = 0; x < width; ++x) {
    T value;
    std::memcpy(&value, row + x * sizeof(T), sizeof(T));
    const double v = static_cast<double>(value);
    out[x] = low <= v && v <= high;
  }
}

}  // namespace

ValueRangeSource::ValueRangeSource(std::unique_ptr<SliceSource> inner, double low, double high)
    : inner_(std::move(inner)), info_(inner_->info()), low_(low), high_(high) {
  info_.type = SampleType::u8;
  mask_.resize(std::size_t{info_.width} * info_.height);
}

bool ValueRangeSource::next_slice(SliceView* slice) {
  SliceView in;
  if (!inner_->next_slice(&in)) return false;
  const auto* base = static_cast<const unsigned char*>(in.samples);
  for (std::uint32_t y = 0; y < in.height; ++y) {
    const unsigned char* row = base + std::size_t{y} * in.row_stride_bytes;
    std::uint8_t* out = mask_.data() + std::size_t{y} * in.width;
    switch (in.type) {
      case SampleType::u8: mask_row<std::uint8_t>(row, in.width, low_, high_, out); break;
      case SampleType::u16: mask_row<std::uint16_t>(row, in.width, low_, high_, out); break;
      case SampleType::i16: mask_row<std::int16_t>(row, in.width, low_, high_, out); break;
      case SampleType::f32: mask_row<float>(row, in.width, low_, high_, out); break;
    }
  }
  slice->samples = mask_.data();
  slice->width = in.width;
  slice->height = in.height;
  slice->row_stride_bytes = in.width;
  slice->type = SampleType::u8;
  return true;
}

}  // namespace mvox
