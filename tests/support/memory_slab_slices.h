#pragma once
// An 8-bit volume's slices from memory, as a slab worker gets them (pipeline/slab_engine_run.h),
// for tests that extract slabs by hand.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mvox/engine.h"
#include "pipeline/slab_engine_run.h"

namespace mvox::test {

class MemorySlabSlices final : public SlabSlices {
 public:
  MemorySlabSlices(const std::vector<std::uint8_t>& samples, const VolumeInfo& info)
      : samples_(samples), info_(info) {}
  bool next(std::uint32_t z, SliceView* view) override {
    view->samples = samples_.data() + std::size_t{z} * info_.width * info_.height;
    view->width = info_.width;
    view->height = info_.height;
    view->type = SampleType::u8;
    view->row_stride_bytes = info_.width;
    return true;
  }

 private:
  const std::vector<std::uint8_t>& samples_;
  const VolumeInfo& info_;
};

}  // namespace mvox::test
