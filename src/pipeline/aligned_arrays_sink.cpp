#include "pipeline/aligned_arrays_sink.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mvox {

AlignedArraysSink::AlignedArraysSink(const WorldTransform& placement, std::uint32_t depth,
                                     const std::string& label, std::uint64_t first_vertex)
    : placement_(placement), depth_(depth), label_(label), first_vertex_(first_vertex) {
  identity_ = true;
  for (int axis = 0; axis < 3; ++axis)
    identity_ = identity_ && placement.spacing[axis] == 1.0 && placement.origin[axis] == 0.0;
}

template <class Take>
Status AlignedArraysSink::caught(Take take) {
  try {
    return take();
  } catch (...) {
    thrown_ = std::current_exception();
    return Status::sink_refused;
  }
}

Status AlignedArraysSink::consume_vertices(const Vertex* vertices, std::size_t vertex_count) {
  return caught([&] { return take_vertices(vertices, vertex_count); });
}

Status AlignedArraysSink::consume_polygons(const Polygon* polygons, std::size_t polygon_count) {
  return caught([&] { return take_polygons(polygons, polygon_count); });
}

void AlignedArraysSink::trim() {
  auto fit = [](auto& array) {
    if (array.capacity() > 2 * array.size() + (std::size_t{1} << 20)) array.shrink_to_fit();
  };
  fit(mesh_.vertices);
  fit(mesh_.polygon_offsets);
  fit(mesh_.polygon_indices);
  fit(mesh_.wide_polygon_indices);
}

Status AlignedArraysSink::take_vertices(const Vertex* vertices, std::size_t vertex_count) {
  const std::size_t first = mesh_.vertices.size();
  // The share of the volume done so far, from the last vertex's slice (vertices come slice
  // by slice): the arrays are grown once or twice to the size it predicts, rather than
  // doubled a dozen times, each time copying what they hold.
  if (vertex_count > 0)
    done_ = std::min(1.0, (vertices[vertex_count - 1].z + 1.0) / (depth_ + 1.0));
  // One float of room past the batch: append_vertex_positions copies vertices whole.
  grow(mesh_.vertices, first + 3 * vertex_count + 1);
  if (identity_) {
    // Spacing 1 and origin 0: 0 + 1 * v in double is v exactly, so the float is v itself.
    append_vertex_positions(mesh_, vertices, vertex_count);
    return Status::ok;
  }
  mesh_.vertices.resize(first + 3 * vertex_count);
  float* out = mesh_.vertices.data() + first;
  for (std::size_t i = 0; i < vertex_count; ++i, out += 3) {
    const Vector3d world =
        placement_.axis_aligned_position(vertices[i].x, vertices[i].y, vertices[i].z);
    for (int axis = 0; axis < 3; ++axis) {
      // Converting a double beyond float's range is undefined behaviour: refuse as the
      // writers do.
      if (!(std::fabs(world[axis]) <= std::numeric_limits<float>::max())) {
        error_ = Error(label_, "vertex " + std::to_string(first_vertex_ + first / 3 + i) +
                                   " lies outside the float range after spacing and origin");
        return Status::sink_refused;
      }
      out[axis] = static_cast<float>(world[axis]);
    }
  }
  return Status::ok;
}

Status AlignedArraysSink::take_polygons(const Polygon* polygons, std::size_t polygon_count) {
  // Past 2^31 vertices, 64-bit indices (mesh_arrays.h), made whole from the engine's, which
  // are modulo 2^32. Below, the engine's indices are the arrays'.
  const std::uint64_t vertices_taken = first_vertex_ + mesh_.vertex_count();
  if (vertices_taken > kNarrowIndexVertices) {
    if (!mesh_.wide) widen_indices(mesh_);
    grow(mesh_.wide_polygon_indices,
         mesh_.wide_polygon_indices.size() + polygon_count * kMaxPolygonVertices);
    grow(mesh_.polygon_offsets, mesh_.polygon_offsets.size() + polygon_count);
    append_wide_polygons(mesh_, polygons, polygon_count, 0, vertices_taken);
    return Status::ok;
  }
  // Room for seven indices a polygon, append_polygons' slack: the prediction is made from
  // the indices held, so the slack inflates it by one batch at most.
  grow(mesh_.polygon_indices, mesh_.polygon_indices.size() + polygon_count * kMaxPolygonVertices);
  grow(mesh_.polygon_offsets, mesh_.polygon_offsets.size() + polygon_count);
  append_polygons(mesh_, polygons, polygon_count);
  return Status::ok;
}

// Room for `needed` numbers: doubling until a tenth of the volume is done, then what the share
// done predicts for the whole volume, with a margin, and at most 8 times what is held: a
// surface in the first slices of a deep volume must not reserve gigabytes.
template <class Array>
void AlignedArraysSink::grow(Array& array, std::size_t needed) {
  if (needed <= array.capacity()) return;
  if (done_ < 0.1) {
    array.reserve(2 * needed);
    return;
  }
  // Predicted afresh at every growth, so that an early underestimate costs one more copy, not
  // doubling after doubling.
  const double predicted = 1.1 * static_cast<double>(needed) / done_;
  const double capped = std::min(predicted, 8.0 * static_cast<double>(needed));
  array.reserve(std::max<std::size_t>(needed + needed / 8, static_cast<std::size_t>(capped)));
}

}  // namespace mvox
