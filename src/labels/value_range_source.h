#pragma once
// The voxels whose values lie in [low, high], as a 0/1 u8 volume: the source behind --tissue fat
// and soft-tissue, whose surface (threshold 1 on this) encloses a range of values rather than
// everything above one. Streams the inner source slice by slice; one mask slice of memory.
#include <cstdint>
#include <memory>
#include <vector>

#include "mvox/slice_source.h"

namespace mvox {

class ValueRangeSource final : public SliceSource {
 public:
  ValueRangeSource(std::unique_ptr<SliceSource> inner, double low, double high);

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override { return inner_->working_bytes() + mask_.size(); }

 private:
  std::unique_ptr<SliceSource> inner_;
  VolumeInfo info_;
  double low_, high_;
  std::vector<std::uint8_t> mask_;
};

}  // namespace mvox
