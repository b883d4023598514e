#include "picture/mesh_render.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

namespace mvox {
namespace {

glm::vec3 position(const PlyMesh& mesh, std::uint32_t index) {
  const std::array<float, 3>& p = mesh.positions[index];
  return glm::vec3(p[0], p[1], p[2]);
}

}  // namespace

std::vector<std::array<float, 3>> area_weighted_normals(const PlyMesh& mesh) {
  std::vector<glm::dvec3> sums(mesh.vertex_count(), glm::dvec3(0.0));
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t first = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    // Newell: twice the vector area of the polygon, planar or not.
    glm::dvec3 area(0.0);
    for (std::uint32_t k = first; k < end; ++k) {
      const glm::dvec3 a(position(mesh, mesh.face_indices[k]));
      const glm::dvec3 b(position(mesh, mesh.face_indices[k + 1 < end ? k + 1 : first]));
      area += glm::cross(a, b);
    }
    for (std::uint32_t k = first; k < end; ++k) sums[mesh.face_indices[k]] += area;
  }
  std::vector<std::array<float, 3>> normals(mesh.vertex_count(), {0.0f, 0.0f, 0.0f});
  for (std::size_t v = 0; v < sums.size(); ++v) {
    const double length = glm::length(sums[v]);
    if (length > 0.0 && std::isfinite(length))
      for (int axis = 0; axis < 3; ++axis)
        normals[v][axis] = static_cast<float>(sums[v][axis] / length);
  }
  return normals;
}

bool face_bounds(const PlyMesh& mesh, glm::vec3* box_min, glm::vec3* box_max) {
  glm::vec3 low(std::numeric_limits<float>::max()), high(-std::numeric_limits<float>::max());
  for (const std::uint32_t index : mesh.face_indices) {
    low = glm::min(low, position(mesh, index));
    high = glm::max(high, position(mesh, index));
  }
  if (mesh.face_indices.empty()) return false;
  *box_min = low;
  *box_max = high;
  return true;
}

void draw_mesh(const PlyMesh& mesh, const std::vector<std::array<float, 3>>& normals,
               ZBufferRenderer& renderer) {
  constexpr std::uint32_t kMostAtOnce = 16;  // the renderer's polygon limit
  const bool smooth = !normals.empty();
  glm::vec3 positions[kMostAtOnce], vertex_normals[kMostAtOnce];
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::uint32_t first = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    const std::uint32_t count = end - first;
    if (count < 3) continue;
    auto load = [&](std::uint32_t slot, std::uint32_t k) {
      const std::uint32_t index = mesh.face_indices[k];
      positions[slot] = position(mesh, index);
      if (smooth) {
        const std::array<float, 3>& n = normals[index];
        vertex_normals[slot] = glm::vec3(n[0], n[1], n[2]);
      }
    };
    if (count <= kMostAtOnce) {
      for (std::uint32_t i = 0; i < count; ++i) load(i, first + i);
      renderer.draw_polygon(positions, smooth ? vertex_normals : nullptr, static_cast<int>(count));
      continue;
    }
    for (std::uint32_t k = first + 1; k + 1 < end; ++k) {  // the same fan, one at a time
      load(0, first);
      load(1, k);
      load(2, k + 1);
      renderer.draw_polygon(positions, smooth ? vertex_normals : nullptr, 3);
    }
  }
}

}  // namespace mvox
