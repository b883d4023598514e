#include "write/mesh/vertex_placement.h"

#include <cmath>
#include <limits>

namespace mvox {

VertexPlacement::VertexPlacement(const WorldTransform& transform, bool with_normals)
    : transform_(transform),
      axis_aligned_(transform.is_axis_aligned()),
      normal_matrix_(transform.normal_matrix()),
      with_normals_(with_normals) {}

std::size_t VertexPlacement::place(const Vertex* vertices, const glm::vec3* normals,
                                   std::size_t count, WorldVertex* out) const {
  for (std::size_t i = 0; i < count; ++i) {
    const Vertex& vertex = vertices[i];
    const Vector3d world = axis_aligned_
                               ? transform_.axis_aligned_position(vertex.x, vertex.y, vertex.z)
                               : transform_.position(vertex.x, vertex.y, vertex.z);
    WorldVertex& placed = out[i];
    for (int axis = 0; axis < 3; ++axis) {
      if (!(std::fabs(world[axis]) <= std::numeric_limits<float>::max())) return i;
      placed.position[axis] = static_cast<float>(world[axis]);
    }
    if (with_normals_) {
      // Identity axes keep the normal exactly as computed: renormalising would change it by an
      // ulp for nothing.
      const glm::vec3 normal =
          axis_aligned_ ? normals[i] : world_normal(normal_matrix_, normals[i]);
      for (int axis = 0; axis < 3; ++axis) placed.normal[axis] = normal[axis];
    }
  }
  return count;
}

}  // namespace mvox
