#include "pipeline/pipeline.h"

#include <chrono>

#include "error.h"
#include "workspace_buffer.h"

namespace mvox {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Forwards every batch to the mesh sink and the render sink (either may be null) and adds up
// the time each takes. A clock reading costs about as much as a small batch, and the engine
// makes up to three calls per slice, so each reading ends one interval and starts the next:
// the mesh sink's end is the render sink's start, and the end of consume_polygons() is the start
// of the consume_polygon_geometry() that the engine makes right after it (polygon_sink.h).
class TimedSinks final : public PolygonSink {
 public:
  explicit TimedSinks(const PipelineSinks& sinks) : mesh_(sinks.mesh), render_(sinks.render) {}
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    return both(Clock::now(),
                [&](PolygonSink& sink) { return sink.consume_vertices(vertices, vertex_count); });
  }
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    const Status status = both(Clock::now(), [&](PolygonSink& sink) {
      return sink.consume_polygons(polygons, polygon_count);
    });
    geometry_start_ = last_reading_;
    return status;
  }
  Status consume_polygon_geometry(const PolygonGeometry* polygons,
                                  std::size_t polygon_count) override {
    return both(geometry_start_, [&](PolygonSink& sink) {
      return sink.consume_polygon_geometry(polygons, polygon_count);
    });
  }
  double mesh_seconds = 0;
  double render_seconds = 0;

 private:
  template <class Call>
  Status both(Clock::time_point start, Call call) {
    Status status = Status::ok;
    last_reading_ = start;
    if (mesh_) status = timed(*mesh_, call, mesh_seconds);
    if (render_ && status == Status::ok) status = timed(*render_, call, render_seconds);
    return status;
  }
  // Calls `sink` from the last reading on, and takes the next.
  template <class Call>
  Status timed(PolygonSink& sink, Call& call, double& seconds) {
    const Status status = call(sink);
    const auto now = Clock::now();
    seconds += std::chrono::duration<double>(now - last_reading_).count();
    last_reading_ = now;
    return status;
  }

  PolygonSink* mesh_;
  PolygonSink* render_;
  Clock::time_point last_reading_;
  Clock::time_point geometry_start_;  // the end of the last consume_polygons()
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

PipelineResult run_pipeline(SliceSource& source, double threshold, const EngineOptions& options,
                            PolygonSink& sink, const std::string& input_label,
                            const SliceProgress& progress) {
  PipelineSinks sinks;
  sinks.mesh = &sink;
  return run_pipeline(source, threshold, options, sinks, input_label, progress);
}

PipelineResult run_pipeline(SliceSource& source, double threshold,
                            const EngineOptions& requested_options, const PipelineSinks& sinks,
                            const std::string& input_label, const SliceProgress& progress,
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
  TimedSinks timed_sink(sinks);
  Engine engine;
  const Status init = engine.init(workspace.data(), workspace.bytes(), info.width, info.height,
                                  threshold, options, &timed_sink);
  if (init != Status::ok)
    throw Error(input_label, std::string("cannot start: ") + status_message(init));

  TimedSource timed_source(source);
  SliceSource& streamed = source_seconds ? source : timed_source;
  const auto start = Clock::now();
  result.status = stream_volume(streamed, engine, progress, sinks.window);
  result.times.total_s = seconds_since(start);
  result.times.read_s = source_seconds ? source_seconds() : timed_source.seconds;
  result.times.write_s = timed_sink.mesh_seconds;
  result.times.render_s = timed_sink.render_seconds;
  result.times.extract_s =
      result.times.total_s - result.times.read_s - result.times.write_s - result.times.render_s;
  result.counters = engine.counters();
  return result;
}

}  // namespace mvox
