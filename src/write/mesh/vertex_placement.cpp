#include "write/mesh/vertex_placement.h"

#include <algorithm>
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
  if (axis_aligned_ && !with_normals_) return place_axis_aligned(vertices, count, out);
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

std::size_t VertexPlacement::place_axis_aligned(const Vertex* vertices, std::size_t count,
                                                WorldVertex* out) const {
  // The common case (no normals, identity axes), without a branch per vertex: each coordinate
  // is clamped into float's range before it is converted (converting one outside is undefined
  // behaviour) and whether all were inside is folded over the batch; only a batch with one
  // outside is placed again the careful way, to find the first.
  constexpr double kLargest = std::numeric_limits<float>::max();
  const double origin[3] = {transform_.origin[0], transform_.origin[1], transform_.origin[2]};
  const double spacing[3] = {transform_.spacing[0], transform_.spacing[1], transform_.spacing[2]};
  bool inside = true;
  for (std::size_t i = 0; i < count; ++i) {
    const float coordinates[3] = {vertices[i].x, vertices[i].y, vertices[i].z};
    for (int axis = 0; axis < 3; ++axis) {
      // The same sum as WorldTransform::axis_aligned_position, so the same floats.
      const double world = origin[axis] + spacing[axis] * coordinates[axis];
      inside &= std::fabs(world) <= kLargest;
      out[i].position[axis] = static_cast<float>(std::min(std::max(world, -kLargest), kLargest));
    }
  }
  if (inside) return count;
  for (std::size_t i = 0; i < count; ++i) {
    const Vector3d world =
        transform_.axis_aligned_position(vertices[i].x, vertices[i].y, vertices[i].z);
    for (int axis = 0; axis < 3; ++axis)
      if (!(std::fabs(world[axis]) <= kLargest)) return i;
  }
  return count;  // not reached: some coordinate was outside
}

}  // namespace mvox
