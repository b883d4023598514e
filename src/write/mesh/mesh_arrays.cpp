#include "write/mesh/mesh_arrays.h"

#include <utility>

namespace mvox {

MeshArraysWriter::MeshArraysWriter(const MeshWriterOptions& options, std::string subject)
    : MeshWriter(options, Faces::as_polygons, Positions::not_needed),
      subject_(std::move(subject)) {}

void MeshArraysWriter::write_vertices(const WorldVertex* vertices, std::size_t vertex_count) {
  const bool with_normals = options().normals != nullptr;
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const WorldVertex& vertex = vertices[i];
    arrays_.vertices.insert(arrays_.vertices.end(), vertex.position, vertex.position + 3);
    if (with_normals)
      arrays_.normals.insert(arrays_.normals.end(), vertex.normal, vertex.normal + 3);
  }
}

void MeshArraysWriter::write_faces(const Polygon* faces, const FacePositions*,
                                   std::size_t face_count) {
  for (std::size_t i = 0; i < face_count; ++i) {
    const Polygon& face = faces[i];
    for (int k = 0; k < face.vertex_count; ++k)
      arrays_.polygon_indices.push_back(static_cast<std::int32_t>(face.vertices[k]));
    arrays_.polygon_offsets.push_back(static_cast<std::int64_t>(arrays_.polygon_indices.size()));
  }
}

}  // namespace mvox
