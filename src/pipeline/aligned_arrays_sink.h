#pragma once
// The sink of mvox.extract's common case (array_extraction.h): axis-aligned placement that does
// not mirror, polygons as the engine makes them, no normals. Then MeshWriter's work reduces to
// origin + spacing * v per vertex (the very expression of WorldTransform::axis_aligned_position,
// rounded to float as the writers round it) and a copy of each polygon, and its batch copies
// and per-batch checks, which cost as much as extraction itself here, are left out: the
// engine's output is trusted as the core's tests check it.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>

#include "error.h"
#include "mvox/polygon_sink.h"
#include "write/mesh/mesh_arrays.h"
#include "write/mesh/world_transform.h"

namespace mvox {

class AlignedArraysSink : public PolygonSink {
 public:
  // `depth`: the volume's slices, by which the arrays' final size is predicted. `label` names
  // the input in messages (borrowed). `first_vertex`: the vertices the engine numbered before
  // the first it sends here (0 for a whole volume; tests start the engine near 2^31, as
  // detail::number_vertices_from does): the indices count from there.
  AlignedArraysSink(const WorldTransform& placement, std::uint32_t depth, const std::string& label,
                    std::uint64_t first_vertex = 0);

  // The engine is built without exceptions: nothing may leave these calls. A failure is kept
  // and the engine told to stop; the caller rethrows it (thrown(), else error()).
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override;
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override;

  MeshArrays& mesh() { return mesh_; }
  const std::optional<Error>& error() const { return error_; }
  std::exception_ptr thrown() const { return thrown_; }

  // Gives back what the predictions reserved beyond the mesh, when that is much.
  void trim();

 private:
  // take() run so that nothing leaves it: a throw is kept (thrown()) and refuses the batch.
  template <class Take>
  Status caught(Take take);
  Status take_vertices(const Vertex* vertices, std::size_t vertex_count);
  Status take_polygons(const Polygon* polygons, std::size_t polygon_count);
  template <class Array>
  void grow(Array& array, std::size_t needed);

  const WorldTransform& placement_;
  std::uint32_t depth_;
  bool identity_ = false;  // spacing 1, origin 0
  double done_ = 0;        // of the volume, by the last vertex's slice
  const std::string& label_;
  std::uint64_t first_vertex_;
  MeshArrays mesh_;
  std::optional<Error> error_;
  std::exception_ptr thrown_;
};

}  // namespace mvox
