#pragma once
// Drives an engine from any slice source (a file reader or the simulated scanner): the one loop
// every caller would otherwise write.
#include <cstdint>
#include <functional>

#include "mvox/engine.h"
#include "mvox/slice_source.h"

namespace mvox {

// Called after each slice with the number of slices pushed so far.
using SliceProgress = std::function<void(std::uint32_t slices_done)>;

// Pushes every slice of `source` into `engine` (already initialised for the source's width and
// height) and finishes the volume. Returns the first engine error; reader errors propagate as
// the reader's exceptions.
Status stream_volume(SliceSource& source, Engine& engine, const SliceProgress& progress = {});

}  // namespace mvox
