#pragma once
// Reads a volume stored as one headerless file of all slices back to back, e.g.
// engine_256x256x128_uint8.raw (--raw 256x256x128:u8).
#include <cstdint>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "raw_file.h"
#include "raw_format.h"

namespace mvox {

// The file must hold exactly format.depth * format.slice_bytes() bytes (format.depth >= 1);
// slice k starts at byte k * format.slice_bytes(). The file stays open; slices are read one at
// a time at their offset, never the whole volume. A pipe or FIFO is read in order, and its
// length is checked as it arrives: a short one fails at the slice where it ends, a long one
// after the last slice.
// info(): format's width, height, depth and type, spacing 1,1,1.
// Memory: one slice buffer, reused, allocated at the first slice (not by the constructor, so
// that a run's memory plan can refuse it first); samples are swapped to native order in place.
// Throws mvox::Error naming the file when it cannot be opened, has the wrong size, or a read
// fails.
class RawVolumeSource : public SliceSource {
 public:
  RawVolumeSource(const std::string& path, const RawFormat& format);

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override { return format_.slice_bytes(); }

 private:
  RawFile file_;
  RawFormat format_;
  VolumeInfo info_;
  std::vector<unsigned char> buffer_;  // the current slice, native order
  std::uint32_t next_index_ = 0;
};

}  // namespace mvox
