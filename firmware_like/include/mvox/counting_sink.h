#pragma once
// A polygon sink that only counts: for benchmarks, for measuring the engine alone, and for
// devices that need the statistics of a scan but not its mesh. It allocates nothing, so it
// cannot disturb an allocation count. It can refuse a chosen batch, to exercise the engine's
// refusal path.
#include <cstddef>
#include <cstdint>

#include "mvox/polygon_sink.h"

namespace mvox {

class CountingSink : public PolygonSink {
 public:
  Status consume_vertices(const Vertex*, std::size_t vertex_count) override {
    vertices += vertex_count;
    return next_batch();
  }
  Status consume_polygons(const Polygon*, std::size_t polygon_count) override {
    polygons += polygon_count;
    return next_batch();
  }

  std::uint64_t vertices = 0;
  std::uint64_t polygons = 0;
  std::uint64_t batches = 0;
  std::uint64_t refuse_batch = 0;  // 1-based number of the batch to refuse; 0: refuse none

 private:
  Status next_batch() { return ++batches == refuse_batch ? Status::sink_refused : Status::ok; }
};

}  // namespace mvox
