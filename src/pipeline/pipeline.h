#pragma once
// One extraction, source to sink, with the time spent in each phase: what `mvox extract`,
// `mvox demo` and the benchmarks all run.
#include <cstdint>
#include <functional>
#include <string>

#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "mvox/stream_volume.h"
#include "postprocess/layer_decimation.h"

namespace mvox {

struct PhaseTimes {
  double read_s = 0;     // inside the slice source: file reading, decoding, byte swapping
  double extract_s = 0;  // inside the engine, minus the time its sink took
  double write_s = 0;    // inside the mesh sink (writing the mesh)
  double render_s = 0;   // inside the render sink (drawing the picture); run_mesh_job adds the
                         // frames written and the live window's updates (with slab workers,
                         // compositing their layers for them too)
  double total_s = 0;    // wall clock from the first slice to the engine's finish()
};

// What the decimation took and gave, when there was one.
struct DecimationCounts {
  std::uint64_t triangles_in = 0;
  std::uint64_t triangles_out = 0;
  std::uint64_t vertices_out = 0;
};

struct PipelineResult {
  Status status = Status::ok;  // the engine's; sink_refused means the sink holds the reason
  EngineCounters counters;
  DecimationCounts decimation;
  PhaseTimes times;
  std::size_t workspace_bytes = 0;
  // Slab workers: the most chunks of recorded output one of them held
  // (SlabWriteTurns::most_chunks_taken); 0 for one engine.
  unsigned slab_chunks_taken = 0;
};

// Where the engine's output goes; every member may be null.
struct PipelineSinks {
  PolygonSink* mesh = nullptr;    // timed as write_s
  PolygonSink* render = nullptr;  // timed as render_s; gets polygons by value
  // Feeds the engine one slice behind the source, for gradient normals (mvox/stream_volume.h).
  // With smoothing it must hold smooth_window_depth() slices: normals are then asked for
  // vertices that many layers after the engine made them.
  SliceWindow* window = nullptr;
  // --smooth N: the engine's output smoothed (postprocess/edge_smoothing.h) before the mesh and
  // render sinks get it; 0 for none.
  std::uint32_t smooth_iterations = 0;
  // --decimate / --max-error: the output simplified (postprocess/layer_decimation.h) after any
  // smoothing; null for none.
  const DecimationOptions* decimation = nullptr;
};

// The slices a normals window must hold when the output is smoothed `iterations` times: the
// smoothing holds N + 1 layers back, and the engine is fed one slice behind the window.
std::uint32_t smooth_window_depth(std::uint32_t iterations);

// The seconds a source has spent reading so far, for a source that times itself.
using SourceSeconds = std::function<double()>;

// Called after each slice the engine has taken, with the number taken so far (the core's
// SliceProgress, as a std::function for hosts).
using ProgressCallback = std::function<void(std::uint32_t slices_done)>;

// Streams every slice of `source` through a new engine into the sinks and finishes the volume.
// The engine sends polygons by value (EngineOptions::polygon_geometry) when there is a render
// sink. Throws mvox::Error naming `input_label` when the engine refuses the source (for example
// slices too large to address).
// The read time is `source_seconds()` when given (PrefetchingSource::seconds_waiting, which
// knows when it waits); otherwise every next_slice() call is timed, two clock readings a slice.
// `progress` is not timed, for the same reason: it counts as extraction unless the caller takes
// out the time it spent there (run_mesh_job does for frames and the live window).
PipelineResult run_pipeline(SliceSource& source, double threshold, const EngineOptions& options,
                            const PipelineSinks& sinks, const std::string& input_label,
                            const ProgressCallback& progress = {},
                            const SourceSeconds& source_seconds = {});

// The same with one mesh sink.
PipelineResult run_pipeline(SliceSource& source, double threshold, const EngineOptions& options,
                            PolygonSink& sink, const std::string& input_label,
                            const ProgressCallback& progress = {});

}  // namespace mvox
