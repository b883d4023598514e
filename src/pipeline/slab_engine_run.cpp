#include "pipeline/slab_engine_run.h"

#include <algorithm>
#include <utility>

#include "error.h"
#include "mvox/fan_out_sink.h"
#include "pipeline/stopwatch.h"

namespace mvox {

Error slices_ended_early(const std::string& input_label, std::uint32_t z, std::uint32_t depth) {
  return Error(input_label,
               "ended after " + std::to_string(z) + " of its " + std::to_string(depth) + " slices");
}

SlabSpan SlabSpan::of(std::uint32_t first, std::uint32_t end, std::uint32_t depth, bool normals) {
  const std::uint32_t extra = normals ? 1 : 0;
  SlabSpan span;
  span.first = first;
  span.end = end;
  span.read_from = first == 0 ? 0 : first - std::min(first, 1 + extra);
  span.read_to = std::min(depth, end + extra);
  return span;
}

OwnReaderSlices::OwnReaderSlices(SliceSource& reader, const std::string& input_label,
                                 std::uint32_t depth, const Cancellation* cancellation,
                                 Failed failed)
    : reader_(reader),
      input_label_(input_label),
      depth_(depth),
      cancellation_(cancellation),
      failed_(std::move(failed)) {}

bool OwnReaderSlices::next(std::uint32_t z, SliceView* view) {
  if (cancellation_ && cancellation_->cancelled()) return false;
  std::exception_ptr failure;
  const auto start = Clock::now();
  try {
    if (!reader_.next_slice(view)) throw slices_ended_early(input_label_, z, depth_);
  } catch (...) {
    failure = std::current_exception();
  }
  read_seconds_ += seconds_since(start);
  if (!failure) return true;
  if (!failed_) std::rethrow_exception(failure);
  failed_(z, failure);
  return false;
}

bool extract_slab(const SlabSpan& span, const VolumeInfo& info, double threshold,
                  const EngineOptions& options, void* workspace, std::size_t workspace_bytes,
                  SlabRecorder& recorder, PolygonSink* drawing, SliceWindow* window,
                  SlabSlices& slices, const Cancellation& cancellation,
                  const std::string& input_label) {
  auto check = [&](Status status) {
    if (status == Status::ok) return true;
    if (cancellation.cancelled()) return false;  // the recorder found the run cancelled
    throw Error(input_label, std::string("extraction failed: ") + status_message(status));
  };
  FanOutSink both;
  both.add(&recorder);
  both.add(drawing);
  Engine engine;
  if (!check(engine.init(workspace, workspace_bytes, info.width, info.height, threshold, options,
                         drawing ? static_cast<PolygonSink*>(&both) : &recorder)))
    return false;
  if (span.first == 0) {
    if (!recorder.start(0)) return false;
    recorder.own_vertices_only();  // the first slab has no shared vertices
  }
  std::uint64_t last_slice_first_vertex = 0;
  // The engine's part of slice z: the slice before the slab starts it, the slab's own are
  // pushed, the window's extra ones are only for normals.
  auto take = [&](std::uint32_t z, const SliceView& view) {
    if (span.first > 0 && z + 1 == span.first) {
      return check(engine.begin_slab(view, span.first)) &&
             recorder.start(engine.counters().shared_vertices);
    }
    if (z < span.first || z >= span.end) return true;
    last_slice_first_vertex = engine.counters().vertices;
    if (!check(engine.push_slice(view))) return false;
    if (z == span.first) recorder.own_vertices_only();
    return true;
  };
  if (window) window->restart_at(span.read_from);
  for (std::uint32_t z = span.read_from; z < span.read_to; ++z) {
    SliceView view;
    if (!slices.next(z, &view)) return false;
    bool ok = true;
    if (window) {
      // As stream_volume() does: the engine one slice behind the window, so that the window
      // holds z - 2 .. z + 1 while the engine emits slice z's vertices.
      if (!check(window->push(view))) return false;
      if (z > span.read_from) ok = take(z - 1, window->slice(z - 1));
    } else {
      ok = take(z, view);
    }
    slices.release();
    if (!ok) return false;
    recorder.poll();
  }
  if (window && !take(span.read_to - 1, window->slice(span.read_to - 1))) return false;
  if (!check(span.end == info.depth ? engine.finish() : engine.finish_slab())) return false;
  recorder.end({engine.counters(), last_slice_first_vertex});
  return true;
}

}  // namespace mvox
