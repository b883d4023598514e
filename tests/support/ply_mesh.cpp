#include "ply_mesh.h"

namespace mvox::test {

Mesh mesh_of_positions(const std::vector<std::array<float, 3>>& positions) {
  Mesh mesh;
  mesh.vertices.reserve(positions.size());
  for (const auto& p : positions) {
    Vertex v;
    v.x = p[0];
    v.y = p[1];
    v.z = p[2];
    mesh.vertices.push_back(v);
  }
  return mesh;
}

Mesh to_mesh(const PlyMesh& ply) {
  Mesh mesh = mesh_of_positions(ply.positions);
  mesh.polygons.reserve(ply.face_count());
  for (std::size_t f = 0; f < ply.face_count(); ++f)
    mesh.polygons.emplace_back(ply.face_indices.begin() + ply.face_offsets[f],
                               ply.face_indices.begin() + ply.face_offsets[f + 1]);
  return mesh;
}

}  // namespace mvox::test
