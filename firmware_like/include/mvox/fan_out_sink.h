#pragma once
// One engine, several sinks: a mesh writer and a renderer, a writer and a counter. Fixed size,
// no heap.
#include <cstddef>

#include "mvox/polygon_sink.h"

namespace mvox {

// Which PolygonSink call a FanOutSink is passing on.
enum class SinkCall : unsigned char { vertices, polygons, polygon_geometry };

// Sends every batch to each of its sinks in the order they were added, and stops at the first
// that refuses (returning its status: the engine then stops, and later sinks never see the
// batch). An optional observer is told before the first sink's call (sink -1) and after each
// sink's call (its index), which is all a host needs to time each sink with one clock reading
// per call, the end of one sink's call being the start of the next.
class FanOutSink final : public PolygonSink {
 public:
  static constexpr int kMaxSinks = 8;
  using Observer = void (*)(void* context, SinkCall call, int sink);

  FanOutSink() = default;
  FanOutSink(const FanOutSink&) = delete;
  FanOutSink& operator=(const FanOutSink&) = delete;

  // Adds `sink` (borrowed; null is ignored). Returns false when kMaxSinks are already there.
  bool add(PolygonSink* sink) {
    if (sink == nullptr) return true;
    if (count_ == kMaxSinks) return false;
    sinks_[count_++] = sink;
    return true;
  }
  void set_observer(Observer observer, void* context) {
    observer_ = observer;
    observer_context_ = context;
  }
  int size() const { return count_; }

  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    return each(SinkCall::vertices,
                [&](PolygonSink& sink) { return sink.consume_vertices(vertices, vertex_count); });
  }
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    return each(SinkCall::polygons,
                [&](PolygonSink& sink) { return sink.consume_polygons(polygons, polygon_count); });
  }
  Status consume_polygon_geometry(const PolygonGeometry* polygons,
                                  std::size_t polygon_count) override {
    return each(SinkCall::polygon_geometry, [&](PolygonSink& sink) {
      return sink.consume_polygon_geometry(polygons, polygon_count);
    });
  }

 private:
  template <class Call>
  Status each(SinkCall call, const Call& forward) {
    if (observer_) observer_(observer_context_, call, -1);
    for (int i = 0; i < count_; ++i) {
      const Status status = forward(*sinks_[i]);
      if (observer_) observer_(observer_context_, call, i);
      if (status != Status::ok) return status;
    }
    return Status::ok;
  }

  PolygonSink* sinks_[kMaxSinks] = {};
  int count_ = 0;
  Observer observer_ = nullptr;
  void* observer_context_ = nullptr;
};

}  // namespace mvox
