#include "write/mesh/vertex_placement.h"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

#include "write/mesh/axis_aligned_placement.h"
#include "write/mesh/little_endian.h"

#if defined(__SSE2__)
#define MVOX_PLACEMENT_SSE2 1
#else
#define MVOX_PLACEMENT_SSE2 0
#endif

namespace mvox {

VertexPlacement::VertexPlacement(const WorldTransform& transform, bool with_normals)
    : transform_(transform),
      axis_aligned_(transform.is_axis_aligned()),
      identity_(axis_aligned_ && is_identity_placement(transform)),
      normal_matrix_(transform.normal_matrix()),
      with_normals_(with_normals) {}

#if MVOX_PLACEMENT_SSE2
static_assert(offsetof(WorldVertex, position) == 0 && offsetof(WorldVertex, normal) == 12,
              "a placed vertex's position is followed by its normal: one 16-byte store");
#endif

bool VertexPlacement::world_floats(const Vertex& vertex, float position[3]) const {
  const Vector3d world = axis_aligned_
                             ? transform_.axis_aligned_position(vertex.x, vertex.y, vertex.z)
                             : transform_.position(vertex.x, vertex.y, vertex.z);
  for (int axis = 0; axis < 3; ++axis) {
    if (!(std::fabs(world[axis]) <= std::numeric_limits<float>::max())) return false;
    position[axis] = static_cast<float>(world[axis]);
  }
  return true;
}

std::size_t VertexPlacement::place(const Vertex* vertices, const glm::vec3* normals,
                                   std::size_t count, WorldVertex* out) const {
#if MVOX_PLACEMENT_SSE2
  // The common case, identity axes, in one pass without a branch per vertex; a batch with a
  // vertex beyond float's range goes through the loop below, which names the first.
  if (axis_aligned_ &&
      place_axis_aligned(vertices, count, transform_, identity_,
                         reinterpret_cast<unsigned char*>(out), sizeof(WorldVertex))) {
    if (with_normals_)  // identity axes keep each normal as computed (see below)
      for (std::size_t i = 0; i < count; ++i)
        for (int axis = 0; axis < 3; ++axis) out[i].normal[axis] = normals[i][axis];
    return count;
  }
#endif
  for (std::size_t i = 0; i < count; ++i) {
    WorldVertex& placed = out[i];
    if (!world_floats(vertices[i], placed.position)) return i;
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

std::size_t VertexPlacement::place_positions(const Vertex* vertices, std::size_t count,
                                             unsigned char* out) const {
#if MVOX_PLACEMENT_SSE2 && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  // Packed records of three floats, each vertex one 16-byte store (the 4 bytes past a record
  // are the next record's, or kPositionSlack).
  if (axis_aligned_ && place_axis_aligned(vertices, count, transform_, identity_, out, 12))
    return count;
#endif
  for (std::size_t i = 0; i < count; ++i) {
    float position[3];
    if (!world_floats(vertices[i], position)) return i;
    for (int axis = 0; axis < 3; ++axis) out = store_le_float(out, position[axis]);
  }
  return count;
}

}  // namespace mvox
