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
  virtual Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) = 0;
  virtual Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) = 0;
  // Only with EngineOptions::polygon_geometry: called right after consume_polygons with the
  // same batch, each polygon's vertices given by value. Sinks that index ignore it.
  virtual Status consume_polygon_geometry(const PolygonGeometry* polygons,
                                          std::size_t polygon_count) {
    (void)polygons;
    (void)polygon_count;
    return Status::ok;
  }

 protected:
  // Sinks are never owned or deleted through this interface. A non-virtual destructor keeps
  // operator delete (a deleting destructor) out of the core's sinks, which never allocate.
  ~PolygonSink() = default;
};

}  // namespace mvox
