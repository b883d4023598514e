#include "pipeline/pipeline.h"

#include <chrono>
#include <exception>
#include <optional>

#include "error.h"
#include "mvox/fan_out_sink.h"
#include "mvox/workspace_buffer.h"
#include "pipeline/stopwatch.h"
#include "postprocess/edge_smoothing.h"

namespace mvox {
namespace {

// Times each sink of a FanOutSink (the mesh sink first, then the render sink) as the core tells
// it before and after each call. A clock reading costs about as much as a small batch, and the
// engine makes up to three calls per slice, so each reading ends one interval and starts the
// next: the mesh sink's end is the render sink's start, and the end of consume_polygons() is the
// start of the consume_polygon_geometry() that the engine makes right after it (polygon_sink.h).
class SinkTimes {
 public:
  explicit SinkTimes(FanOutSink& fan_out) { fan_out.set_observer(observe, this); }
  double seconds[FanOutSink::kMaxSinks] = {};

 private:
  static void observe(void* context, SinkCall call, int sink) {
    auto& self = *static_cast<SinkTimes*>(context);
    if (sink < 0) {
      // The geometry call follows consume_polygons at once: its start is that call's end.
      if (call != SinkCall::polygon_geometry) self.last_reading_ = Clock::now();
      return;
    }
    const auto now = Clock::now();
    self.seconds[sink] += std::chrono::duration<double>(now - self.last_reading_).count();
    self.last_reading_ = now;
  }
  Clock::time_point last_reading_;
};

// Times the source's next_slice() calls.
class TimedSource : public SliceSource {
 public:
  explicit TimedSource(SliceSource& source) : source_(source) {}
  const VolumeInfo& info() const override { return source_.info(); }
  bool next_slice(SliceView* slice) override {
    const auto start = Clock::now();
    const bool more = source_.next_slice(slice);
    seconds += seconds_since(start);
    return more;
  }
  double seconds = 0;

 private:
  SliceSource& source_;
};

}  // namespace

std::uint32_t smooth_window_depth(std::uint32_t iterations) {
  return iterations == 0 ? kSliceWindowDepth : iterations + 5;
}

PipelineResult run_pipeline(SliceSource& source, double threshold, const EngineOptions& options,
                            PolygonSink& sink, const std::string& input_label,
                            const ProgressCallback& progress) {
  PipelineSinks sinks;
  sinks.mesh = &sink;
  return run_pipeline(source, threshold, options, sinks, input_label, progress);
}

PipelineResult run_pipeline(SliceSource& source, double threshold,
                            const EngineOptions& requested_options, const PipelineSinks& sinks,
                            const std::string& input_label, const ProgressCallback& progress,
                            const SourceSeconds& source_seconds) {
  const VolumeInfo& info = source.info();
  EngineOptions options = requested_options;
  if (sinks.render) options.polygon_geometry = true;
  PipelineResult result;
  result.workspace_bytes = engine_workspace_bytes(info.width, info.height, options);
  if (result.workspace_bytes == 0)
    throw Error(input_label, "slices of " + std::to_string(info.width) + "x" +
                                 std::to_string(info.height) + " voxels are too large to extract");
  WorkspaceBuffer workspace(result.workspace_bytes);
  FanOutSink fan_out;  // the mesh sink (index 0 when there is one), then the render sink
  fan_out.add(sinks.mesh);
  fan_out.add(sinks.render);
  const int render_index = sinks.mesh ? 1 : 0;
  SinkTimes sink_times(fan_out);
  // Smoothing remakes the polygons by value at the smoothed positions: the engine need not.
  // The chain: engine -> smoothing -> decimation -> the sinks. Each stage after the engine
  // remakes the polygons by value itself, so the engine need not send them.
  PolygonSink* next = &fan_out;
  std::optional<LayerDecimation> decimation;
  if (sinks.decimation) {
    decimation.emplace(*next, *sinks.decimation, options.polygon_geometry);
    next = &*decimation;
  }
  std::optional<EdgeSmoothing> smoothing;
  if (sinks.smooth_iterations > 0) {
    smoothing.emplace(*next, info, sinks.smooth_iterations,
                      options.polygon_geometry && !decimation);
    next = &*smoothing;
  }
  if (smoothing || decimation) options.polygon_geometry = false;
  Engine engine;
  const Status init = engine.init(workspace.data(), workspace.bytes(), info.width, info.height,
                                  threshold, options, next);
  if (init != Status::ok)
    throw Error(input_label, std::string("cannot start: ") + status_message(init));

  TimedSource timed_source(source);
  SliceSource& streamed = source_seconds ? source : timed_source;
  const auto start = Clock::now();
  // Each slice the engine takes completes a layer for the smoothing, before anyone is told.
  const ProgressCallback layer_done = [&](std::uint32_t slices_done) {
    if (smoothing) (void)smoothing->end_layer();  // a failure stops the engine at its next call
    if (progress) progress(slices_done);
  };
  const SliceProgress slice_progress =
      progress || smoothing ? SliceProgress::of(layer_done) : SliceProgress{};
  result.status = stream_volume(streamed, engine, slice_progress, sinks.window);
  if (smoothing) {
    if (result.status == Status::ok) result.status = smoothing->finish();
    if (smoothing->thrown()) std::rethrow_exception(smoothing->thrown());
  }
  if (decimation) {
    if (result.status == Status::ok) result.status = decimation->finish();
    if (decimation->thrown()) std::rethrow_exception(decimation->thrown());
    result.decimation = {decimation->triangles_in(), decimation->triangles_out(),
                         decimation->vertices_out()};
  }
  result.times.total_s = seconds_since(start);
  result.times.read_s = source_seconds ? source_seconds() : timed_source.seconds;
  result.times.write_s = sinks.mesh ? sink_times.seconds[0] : 0;
  result.times.render_s = sinks.render ? sink_times.seconds[render_index] : 0;
  result.times.extract_s =
      result.times.total_s - result.times.read_s - result.times.write_s - result.times.render_s;
  result.counters = engine.counters();
  return result;
}

}  // namespace mvox
