#pragma once
// Reads a volume stored as one headerless file per slice, e.g. CThead.1 ... CThead.113
// (--raw 256x256:u16be).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/copied_slices.h"
#include "read/range_readable.h"
#include "read/raw/raw_format.h"
#include "read/read_buffer.h"

namespace mvox {

// Slice k is files[k] (list_input_files sorts them); every file must hold exactly
// format.slice_bytes() bytes, rows packed, in format.byte_order. format.depth must be 0.
// info(): format's width, height and type, depth = files.size(), spacing 1,1,1.
// Memory: one slice buffer, reused, allocated at the first slice; samples are swapped to native
// order in place.
// Throws mvox::Error: the constructor checks every file's size up front (a wrong size found
// after an hour of streaming helps nobody); next_slice names the file on a read error.
class RawSlicesSource : public SliceSource, public RangeReadable, public CopiedSlices {
 public:
  RawSlicesSource(std::vector<std::string> files, const RawFormat& format);

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override { return format_.slice_bytes(); }

  bool range_readable() const override { return true; }
  std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const override;
  bool slices_are_copied() const override { return true; }

 private:
  const std::vector<std::string>& files() const { return *files_; }
  // Shared by the ranges, not copied for every slab (image_stack_source.h says why).
  std::shared_ptr<const std::vector<std::string>> files_;
  RawFormat format_;
  VolumeInfo info_;
  ReadBuffer buffer_;  // the current slice, native order
  std::size_t next_index_ = 0;
  std::size_t end_index_ = SIZE_MAX;  // one past the last file it returns (open_range)
};

}  // namespace mvox
