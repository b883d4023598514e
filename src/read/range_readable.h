#pragma once
// Inputs whose slices can be read from anywhere, by several readers at once: files on disk, one
// per slice or one for the volume. The slab pipeline (pipeline/slab_extraction.h) then gives each
// worker a reader of its own slab's slices, so that decoding runs in parallel too, where a pipe
// is read once, in order, by one thread.
#include <cstdint>
#include <memory>

#include "mvox/slice_source.h"

namespace mvox {

class RangeReadable {
 public:
  // Whether open_range() works for this input (a pipe: no).
  virtual bool range_readable() const = 0;
  // A new source of slices [first, end) of this volume (first < end <= depth) with its own files
  // and buffers, which another thread may read while this one is used elsewhere. Its info() is
  // this volume's, its working_bytes() this source's, and it reads and checks every slice as
  // this source does, with the same messages.
  virtual std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const = 0;

 protected:
  ~RangeReadable() = default;
};

}  // namespace mvox
