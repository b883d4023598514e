#include "write/mesh/mesh_arrays.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <utility>

namespace mvox {

MeshArraysWriter::MeshArraysWriter(const MeshWriterOptions& options, std::string subject)
    : MeshWriter(options, Faces::as_polygons, Positions::not_needed),
      subject_(std::move(subject)) {}

void MeshArraysWriter::write_vertices(const WorldVertex* vertices, std::size_t vertex_count) {
  // Grown once a batch and filled through a pointer: an insert per vertex cost more than the
  // engine took to find it.
  const std::size_t first = arrays_.vertices.size();
  arrays_.vertices.resize(first + 3 * vertex_count);
  float* out = arrays_.vertices.data() + first;
  for (std::size_t i = 0; i < vertex_count; ++i, out += 3)
    for (int axis = 0; axis < 3; ++axis) out[axis] = vertices[i].position[axis];
  if (!options().writes_normals()) return;
  const std::size_t first_normal = arrays_.normals.size();
  arrays_.normals.resize(first_normal + 3 * vertex_count);
  float* normal = arrays_.normals.data() + first_normal;
  for (std::size_t i = 0; i < vertex_count; ++i, normal += 3)
    for (int axis = 0; axis < 3; ++axis) normal[axis] = vertices[i].normal[axis];
}

void MeshArraysWriter::write_faces(const Polygon* faces, const FacePositions*,
                                   std::size_t face_count, std::uint32_t index_offset) {
  if (index_offset == 0) {
    append_polygons(arrays_, faces, face_count);
    return;
  }
  // Moved a run at a time (slab-parallel runs only; Python's arrays come from one engine).
  Polygon moved[256];
  for (std::size_t first = 0; first < face_count; first += std::size(moved)) {
    const std::size_t count = std::min(std::size(moved), face_count - first);
    for (std::size_t i = 0; i < count; ++i) {
      moved[i] = faces[first + i];
      for (int k = 0; k < moved[i].vertex_count; ++k) moved[i].vertices[k] += index_offset;
    }
    append_polygons(arrays_, moved, count);
  }
}

void append_polygons(MeshArrays& arrays, const Polygon* polygons, std::size_t count) {
  const std::size_t first_index = arrays.polygon_indices.size();
  const std::size_t first_face = arrays.polygon_offsets.size();
  arrays.polygon_indices.resize(first_index + count * kMaxPolygonVertices);
  arrays.polygon_offsets.resize(first_face + count);
  std::int32_t* index = arrays.polygon_indices.data() + first_index;
  std::int64_t* offset = arrays.polygon_offsets.data() + first_face;
  std::int64_t at = static_cast<std::int64_t>(first_index);
  static_assert(sizeof(Polygon::vertices[0]) == sizeof(std::int32_t),
                "indices are copied as bytes");
  for (std::size_t i = 0; i < count; ++i) {
    const Polygon& polygon = polygons[i];
    std::memcpy(index, polygon.vertices, sizeof polygon.vertices);  // < 2^31 (vertex_limit): whole
    index += polygon.vertex_count;
    at += polygon.vertex_count;
    *offset++ = at;
  }
  arrays.polygon_indices.resize(static_cast<std::size_t>(at));
}

}  // namespace mvox
