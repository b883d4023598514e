#pragma once
// A volume already in memory, streamed slice by slice without a copy: the source behind the
// Python module's mvox.extract(numpy_array) and any host that holds its volume itself.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "mvox/slice_source.h"
#include "read/copied_slices.h"
#include "read/range_readable.h"

namespace mvox {

// `info.depth` slices of info.width x info.height samples of info.type, slice z starting at
// samples + z * slice_stride_bytes and row y of it y * row_stride_bytes further (numpy's
// strides of a [z, y, x] array). The memory is borrowed: it must stay valid and unchanged while
// the source streams. Samples in the host's byte order. Memory is readable from anywhere, by
// any number of threads: slab workers each stream their own slab of it (RangeReadable).
class MemoryVolumeSource : public SliceSource, public RangeReadable, public CopiedSlices {
 public:
  MemoryVolumeSource(const void* samples, const VolumeInfo& info, std::ptrdiff_t slice_stride_bytes,
                     std::ptrdiff_t row_stride_bytes)
      : samples_(static_cast<const unsigned char*>(samples)),
        info_(info),
        slice_stride_(slice_stride_bytes),
        row_stride_(row_stride_bytes),
        end_(info.depth) {}

  const VolumeInfo& info() const override { return info_; }

  bool range_readable() const override { return true; }
  bool slices_are_copied() const override { return true; }
  std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const override {
    auto range = std::make_unique<MemoryVolumeSource>(samples_, info_, slice_stride_, row_stride_);
    range->next_ = first;
    range->end_ = end < info_.depth ? end : info_.depth;
    return range;
  }

  bool next_slice(SliceView* slice) override {
    if (next_ >= end_) return false;
    slice->samples = samples_ + static_cast<std::ptrdiff_t>(next_) * slice_stride_;
    slice->width = info_.width;
    slice->height = info_.height;
    slice->row_stride_bytes = static_cast<std::size_t>(row_stride_);
    slice->type = info_.type;
    ++next_;
    return true;
  }

 private:
  const unsigned char* samples_;
  VolumeInfo info_;
  std::ptrdiff_t slice_stride_;
  std::ptrdiff_t row_stride_;
  std::uint32_t next_ = 0;
  std::uint32_t end_;  // one past the last slice this source streams
};

}  // namespace mvox
