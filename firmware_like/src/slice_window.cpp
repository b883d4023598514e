#include "mvox/slice_window.h"

#include <cstring>

#include "mvox/assert.h"
#include "sample_load.h"

namespace mvox {

std::uint32_t slice_window_slots(std::uint32_t depth) {
  if (depth > (1u << 30)) return 0;
  std::uint32_t slots = kSliceWindowDepth;
  while (slots < depth) slots *= 2;
  return slots;
}

std::size_t slice_window_bytes(std::uint32_t width, std::uint32_t height, SampleType type,
                               std::uint32_t depth) {
  const std::uint32_t slots = slice_window_slots(depth);
  if (width == 0 || height == 0 || slots == 0) return 0;
  const std::uint64_t bytes = std::uint64_t{slots} * width * height * sample_bytes(type);
  if (bytes > SIZE_MAX / 2) return 0;
  return static_cast<std::size_t>(bytes);
}

Status SliceWindow::init(void* workspace, std::size_t workspace_bytes, std::uint32_t width,
                         std::uint32_t height, SampleType type, std::uint32_t depth) {
  slots_ = nullptr;
  slices_ = 0;
  first_ = 0;
  const std::size_t needed = slice_window_bytes(width, height, type, depth);
  if (!workspace || needed == 0) return Status::invalid_argument;
  if (workspace_bytes < needed) return Status::workspace_too_small;
  slots_ = static_cast<unsigned char*>(workspace);
  width_ = width;
  height_ = height;
  type_ = type;
  row_bytes_ = std::size_t{width} * sample_bytes(type);
  slots_held_ = slice_window_slots(depth);
  return Status::ok;
}

Status SliceWindow::push(const SliceView& slice) {
  if (!slots_) return Status::not_initialised;
  if (!slice.samples || slice.row_stride_bytes < row_bytes_) return Status::invalid_argument;
  if (slice.width != width_ || slice.height != height_ || slice.type != type_)
    return Status::slice_size_mismatch;
  if (slices_ == UINT32_MAX) return Status::invalid_argument;
  const auto* source = static_cast<const unsigned char*>(slice.samples);
  unsigned char* target = slots_ + std::size_t{slices_ & (slots_held_ - 1)} * height_ * row_bytes_;
  if (slice.row_stride_bytes == row_bytes_) {
    std::memcpy(target, source, row_bytes_ * height_);
  } else {
    for (std::uint32_t y = 0; y < height_; ++y)
      std::memcpy(target + y * row_bytes_, source + y * slice.row_stride_bytes, row_bytes_);
  }
  ++slices_;
  return Status::ok;
}

SliceView SliceWindow::slice(std::uint32_t z) const {
  MVOX_ASSERT(holds(z));
  SliceView view;
  view.samples = row(0, z);
  view.width = width_;
  view.height = height_;
  view.row_stride_bytes = row_bytes_;
  view.type = type_;
  return view;
}

double SliceWindow::sample(std::int64_t x, std::int64_t y, std::int64_t z) const {
  MVOX_ASSERT(slices_ > first_);
  const auto clamp = [](std::int64_t v, std::int64_t hi) { return v < 0 ? 0 : v > hi ? hi : v; };
  const auto cx = static_cast<std::uint32_t>(clamp(x, std::int64_t{width_} - 1));
  const auto cy = static_cast<std::uint32_t>(clamp(y, std::int64_t{height_} - 1));
  const auto cz = static_cast<std::uint32_t>(clamp(z, std::int64_t{slices_} - 1));
  MVOX_ASSERT(holds(cz));
  const unsigned char* r = row(cy, cz);
  switch (type_) {
    case SampleType::u8: return load_sample<SampleType::u8>(r, cx);
    case SampleType::u16: return load_sample<SampleType::u16>(r, cx);
    case SampleType::i16: return load_sample<SampleType::i16>(r, cx);
    default: return load_sample<SampleType::f32>(r, cx);
  }
}

}  // namespace mvox
