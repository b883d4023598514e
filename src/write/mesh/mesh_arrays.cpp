#include "write/mesh/mesh_arrays.h"

#include <cstring>
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
  if (options().normals == nullptr) return;
  const std::size_t first_normal = arrays_.normals.size();
  arrays_.normals.resize(first_normal + 3 * vertex_count);
  float* normal = arrays_.normals.data() + first_normal;
  for (std::size_t i = 0; i < vertex_count; ++i, normal += 3)
    for (int axis = 0; axis < 3; ++axis) normal[axis] = vertices[i].normal[axis];
}

void MeshArraysWriter::write_faces(const Polygon* faces, const FacePositions*,
                                   std::size_t face_count) {
  std::size_t corners = 0;
  for (std::size_t i = 0; i < face_count; ++i) corners += faces[i].vertex_count;
  const std::size_t first_index = arrays_.polygon_indices.size();
  const std::size_t first_face = arrays_.polygon_offsets.size();
  // Each face's seven index slots are copied whole, without a branch on its size, and the next
  // face overwrites the unused ones: room for one face's slack, trimmed at the end.
  arrays_.polygon_indices.resize(first_index + corners + kMaxPolygonVertices);
  arrays_.polygon_offsets.resize(first_face + face_count);
  std::int32_t* index = arrays_.polygon_indices.data() + first_index;
  std::int64_t* offset = arrays_.polygon_offsets.data() + first_face;
  std::int64_t at = static_cast<std::int64_t>(first_index);
  static_assert(sizeof(Polygon::vertices[0]) == sizeof(std::int32_t), "indices are copied as bytes");
  for (std::size_t i = 0; i < face_count; ++i) {
    const Polygon& face = faces[i];
    std::memcpy(index, face.vertices, sizeof face.vertices);  // indices < 2^31 (kMaxVertexCount)
    index += face.vertex_count;
    at += face.vertex_count;
    *offset++ = at;
  }
  arrays_.polygon_indices.resize(first_index + corners);
}

}  // namespace mvox
