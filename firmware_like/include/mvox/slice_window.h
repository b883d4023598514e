#pragma once
// The last few slices' samples, kept for what needs densities around a vertex after the engine
// has classified them away: gradient normals (vertex_normals.h). Memory is the caller's, sized
// by slice_window_bytes(); nothing is allocated after init().
//
// Normals of the vertices that slice z completes need the gradient at slices z - 1 and z, that
// is samples of slices z - 2 .. z + 1. So a caller that wants normals copies each slice here
// first and feeds the engine one slice behind (the window's stored copy of slice z while slice
// z + 1 is the newest), then the last slice after the source ends (stream_volume.h does this).
#include <cstddef>
#include <cstdint>

#include "mvox/slice.h"
#include "mvox/status.h"

namespace mvox {

// Slices held: z - 2 .. z + 1 around the engine's current slice z.
constexpr std::uint32_t kSliceWindowDepth = 4;

// The slices a window asked to hold `depth` slices holds: at least kSliceWindowDepth, rounded
// up to a power of two (a slice's slot is then a mask of its number, as cheap as with four).
// 0 when `depth` is too large. A deeper window serves callers that ask about vertices some
// layers after the engine made them (a smoothing stage that holds layers back).
std::uint32_t slice_window_slots(std::uint32_t depth);

// Bytes of workspace for a window over slices of width x height samples of `type`, holding
// `depth` slices: slice_window_slots(depth) * width * height * sample_bytes(type). 0 when a
// size is 0 or too large.
std::size_t slice_window_bytes(std::uint32_t width, std::uint32_t height, SampleType type,
                               std::uint32_t depth = kSliceWindowDepth);

class SliceWindow {
 public:
  SliceWindow() = default;
  SliceWindow(const SliceWindow&) = delete;
  SliceWindow& operator=(const SliceWindow&) = delete;

  // Prepares an empty window over `workspace` (borrowed; at least slice_window_bytes() bytes
  // for the same `depth`, any alignment), holding slice_window_slots(depth) slices. May be
  // called again to start a new volume.
  Status init(void* workspace, std::size_t workspace_bytes, std::uint32_t width,
              std::uint32_t height, SampleType type, std::uint32_t depth = kSliceWindowDepth);

  // Empties the window and numbers the next slice pushed `first_slice`: for a slab of a larger
  // volume (Engine::begin_slab), whose slices keep their numbers in the volume. init() starts
  // at 0.
  void restart_at(std::uint32_t first_slice) {
    first_ = first_slice;
    slices_ = first_slice;
  }

  // Copies `slice` in as slice number slices(); the oldest slice held is dropped.
  Status push(const SliceView& slice);

  // The number the next slice pushed gets: the slices pushed so far, counted from the first
  // one's number. The window holds slices max(first, slices() - slots()) .. slices() - 1.
  std::uint32_t slices() const { return slices_; }
  bool holds(std::int64_t z) const {
    return z >= std::int64_t{first_} && z < std::int64_t{slices_} &&
           z + slots_held_ >= slices_;
  }

  // A view of held slice `z` (holds(z) must be true); valid until that slot is overwritten,
  // slots() pushes later.
  SliceView slice(std::uint32_t z) const;

  // The sample at voxel (x, y, z) as a double, with x, y clamped to the slice and z clamped to
  // 0 .. slices() - 1 (replicating the border, as central differences at the edge of a volume
  // usually do). After clamping, z must be held.
  double sample(std::int64_t x, std::int64_t y, std::int64_t z) const;

  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  SampleType type() const { return type_; }
  // Start of row y of held slice z (z already clamped and held), for loops that read rows.
  const unsigned char* row(std::uint32_t y, std::uint32_t z) const {
    return slots_ + (std::size_t{z & (slots_held_ - 1)} * height_ + y) * row_bytes_;
  }

  // The number of slices held, slice_window_slots() of the depth asked for.
  std::uint32_t slots() const { return slots_held_; }

 private:
  unsigned char* slots_ = nullptr;  // slots_held_ slices, slice z in slot z & (slots_held_ - 1)
  std::uint32_t slots_held_ = kSliceWindowDepth;
  std::size_t row_bytes_ = 0;
  std::uint32_t width_ = 0;
  std::uint32_t height_ = 0;
  std::uint32_t slices_ = 0;
  std::uint32_t first_ = 0;  // number of the first slice pushed since init() or restart_at()
  SampleType type_ = SampleType::u8;
};

}  // namespace mvox
