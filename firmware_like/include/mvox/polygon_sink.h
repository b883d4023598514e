#pragma once
// Where the engine's output goes, in batches: a mesh writer, a renderer, statistics.
#include <cstddef>

#include "mvox/mesh.h"
#include "mvox/status.h"

namespace mvox {

// Receives vertices and polygons in emission order. Each batch is valid only during the call.
// Vertices are numbered by their position in the stream of all vertex batches (0, 1, 2, ...);
// a polygon's vertices always arrive before the polygon. Returning anything but Status::ok stops
// the engine: it reports Status::sink_refused and sends nothing more.
class PolygonSink {
 public:
  virtual ~PolygonSink() = default;
  virtual Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) = 0;
  virtual Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) = 0;
};

}  // namespace mvox
