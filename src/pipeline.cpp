#include "pipeline.h"

#include <chrono>

#include "error.h"
#include "workspace_buffer.h"

namespace mvox {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Forwards batches to the real sink and adds up the time they take there.
class TimedSink : public PolygonSink {
 public:
  explicit TimedSink(PolygonSink& sink) : sink_(sink) {}
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    const auto start = Clock::now();
    const Status status = sink_.consume_vertices(vertices, vertex_count);
    seconds += seconds_since(start);
    return status;
  }
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    const auto start = Clock::now();
    const Status status = sink_.consume_polygons(polygons, polygon_count);
    seconds += seconds_since(start);
    return status;
  }
  double seconds = 0;

 private:
  PolygonSink& sink_;
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
  const VolumeInfo& info = source.info();
  PipelineResult result;
  result.workspace_bytes = engine_workspace_bytes(info.width, info.height, options);
  if (result.workspace_bytes == 0)
    throw Error(input_label, "slices of " + std::to_string(info.width) + "x" +
                                 std::to_string(info.height) + " voxels are too large to extract");
  WorkspaceBuffer workspace(result.workspace_bytes);
  TimedSink timed_sink(sink);
  Engine engine;
  const Status init = engine.init(workspace.data(), workspace.bytes(), info.width, info.height,
                                  threshold, options, &timed_sink);
  if (init != Status::ok)
    throw Error(input_label, std::string("cannot start: ") + status_message(init));

  TimedSource timed_source(source);
  const auto start = Clock::now();
  result.status = stream_volume(timed_source, engine, progress);
  result.times.total_s = seconds_since(start);
  result.times.read_s = timed_source.seconds;
  result.times.write_s = timed_sink.seconds;
  result.times.extract_s = result.times.total_s - result.times.read_s - result.times.write_s;
  result.counters = engine.counters();
  return result;
}

}  // namespace mvox
