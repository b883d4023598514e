#pragma once
// One extraction of a volume already decoded into memory: the engine and a sink that only
// counts, so a benchmark times the engine alone (no reading, no writing). Shared by the
// benchmarks that report in-memory figures.
#include "mvox/engine.h"
#include "paper_datasets.h"

namespace mvox::bench {

// Runs the engine over every slice of `volume` with `options`; returns the wall time in seconds
// (workspace allocation excluded, init included) and fills `counters`, or -1 when the engine
// refuses.
double extract_in_memory(const LoadedVolume& volume, double threshold, const EngineOptions& options,
                         EngineCounters* counters);

}  // namespace mvox::bench
