#pragma once
// Drives an engine from any slice source (a file reader or the simulated scanner): the one loop
// every caller would otherwise write.
#include <cstdint>
#include <functional>

#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "mvox/slice_window.h"

namespace mvox {

// Called after each slice the engine has taken, with the number of slices it has taken so far.
// Everything that slice completed has reached the sink by then (a frame can be drawn).
using SliceProgress = std::function<void(std::uint32_t slices_done)>;

// Pushes every slice of `source` into `engine` (already initialised for the source's width and
// height) and finishes the volume. Returns the first engine error; reader errors propagate as
// the reader's exceptions.
//
// With a `window` (initialised for the source's slices), each slice is first copied into it and
// the engine takes the window's copy one slice later, so that while the engine emits slice z's
// vertices the window holds slices z - 2 .. z + 1, as gradient normals need (slice_window.h).
Status stream_volume(SliceSource& source, Engine& engine, const SliceProgress& progress = {},
                     SliceWindow* window = nullptr);

}  // namespace mvox
