#pragma once
// Reads a volume stored as one headerless file of all slices back to back, e.g.
// engine_256x256x128_uint8.raw (--raw 256x256x128:u8).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "mvox/slice_source.h"
#include "read/copied_slices.h"
#include "read/range_readable.h"
#include "read/raw/raw_format.h"
#include "read/raw_file.h"

namespace mvox {

// The file must hold exactly format.depth * format.slice_bytes() bytes (format.depth >= 1);
// slice k starts at byte k * format.slice_bytes(). The file stays open; slices are read in
// order, as many as fit in kChunkBytes at a time (one read per slice would cost more than a
// slice of a few bytes takes to extract), never the whole volume. A pipe or FIFO is read as it
// arrives, and its length is checked as it does: a short one fails at the slice where it ends,
// a long one after the last slice.
// info(): format's width, height, depth and type, spacing 1,1,1.
// Memory: max(kChunkBytes, one slice), reused, allocated at the first slice (not by the
// constructor, so that a run's memory plan can refuse it first); samples are swapped to native
// order in place.
// Throws mvox::Error naming the file when it cannot be opened, has the wrong size, or a read
// fails.
class RawVolumeSource : public SliceSource, public RangeReadable, public CopiedSlices {
 public:
  static constexpr std::size_t kChunkBytes = 64 * 1024;

  RawVolumeSource(const std::string& path, const RawFormat& format);

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override { return slices_.buffer_bytes(); }

  // A file, not a pipe: slices [first, end) are read from their place in it.
  bool range_readable() const override { return !file_.is_stream(); }
  std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const override;
  // A pipe's slices come at its writer's pace: worth reading ahead.
  bool slices_are_copied() const override { return !file_.is_stream(); }

 private:
  // Slices [first, end) of the volume file `path`, whose size the whole source checked; with
  // `same_file_as`, the whole source's file, which `path` must still name.
  RawVolumeSource(const std::string& path, const RawFormat& format, std::uint32_t first,
                  std::uint32_t end, const RawFile* same_file_as);

  RawFile file_;
  RawFormat format_;
  VolumeInfo info_;
  ChunkedSliceReader slices_;  // the current slice is swapped to native order in its buffer
  std::uint32_t next_index_ = 0;
  std::uint32_t end_index_ = 0;  // one past the last slice it returns
};

}  // namespace mvox
