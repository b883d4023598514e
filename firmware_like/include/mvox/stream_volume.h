#pragma once
// Drives an engine from any slice source (a file reader or the simulated scanner): the one loop
// every caller would otherwise write. No heap: the progress callback is a function pointer and
// its context, not a std::function.
#include <cstdint>

#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "mvox/slice_window.h"

namespace mvox {

// Told after each slice the engine has taken, with the number of slices it has taken so far;
// everything that slice completed has reached the sink by then (a frame can be drawn). Empty
// (call null) means nobody is told.
struct SliceProgress {
  void (*call)(void* context, std::uint32_t slices_done) = nullptr;
  void* context = nullptr;

  explicit operator bool() const { return call != nullptr; }
  void operator()(std::uint32_t slices_done) const { call(context, slices_done); }

  // Progress that calls `callable(slices_done)`; `callable` is borrowed and must outlive it.
  template <class Callable>
  static SliceProgress of(Callable& callable) {
    return {[](void* context, std::uint32_t slices_done) {
              (*static_cast<Callable*>(context))(slices_done);
            },
            const_cast<void*>(static_cast<const void*>(&callable))};
  }
};

// Pushes every slice of `source` into `engine` (already initialised for the source's width and
// height) and finishes the volume. Returns the first engine error.
//
// A host's source may throw from next_slice() (a file reader's error): the exception passes
// through this loop, which holds nothing to release (its file is built with unwind tables
// although the core has no exceptions), and the engine is left as after a refused slice.
//
// With a `window` (initialised for the source's slices), each slice is first copied into it and
// the engine takes the window's copy one slice later, so that while the engine emits slice z's
// vertices the window holds slices z - 2 .. z + 1, as gradient normals need (slice_window.h).
Status stream_volume(SliceSource& source, Engine& engine, SliceProgress progress = {},
                     SliceWindow* window = nullptr);

}  // namespace mvox
