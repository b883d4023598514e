#include "write/mesh/vertex_placement.h"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

#include "write/mesh/little_endian.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#define MVOX_PLACEMENT_SSE2 1
#else
#define MVOX_PLACEMENT_SSE2 0
#endif

namespace mvox {

namespace {

// Spacing 1 and origin +0 on identity axes: every position is its vertex (see
// place_axis_aligned). An origin of -0 is not: -0 + 1 * -0 is -0, not +0.
bool is_identity(const WorldTransform& transform) {
  for (int axis = 0; axis < 3; ++axis)
    if (transform.spacing[axis] != 1.0 || transform.origin[axis] != 0.0 ||
        std::signbit(transform.origin[axis]))
      return false;
  return true;
}

}  // namespace

VertexPlacement::VertexPlacement(const WorldTransform& transform, bool with_normals)
    : transform_(transform),
      axis_aligned_(transform.is_axis_aligned()),
      identity_(axis_aligned_ && is_identity(transform)),
      normal_matrix_(transform.normal_matrix()),
      with_normals_(with_normals) {}

#if MVOX_PLACEMENT_SSE2
namespace {

static_assert(sizeof(Vertex) == 16 && offsetof(Vertex, x) == 0 && offsetof(Vertex, y) == 4 &&
                  offsetof(Vertex, z) == 8,
              "a vertex is x, y, z and four bytes more: one 16-byte load");
static_assert(offsetof(WorldVertex, position) == 0 && offsetof(WorldVertex, normal) == 12,
              "a placed vertex's position is followed by its normal: one 16-byte store");

// Identity axes: origin + spacing * v per axis, in double as WorldTransform::axis_aligned_position
// computes it (the same two roundings, so the same floats), x and y in one register and z in
// another. Whether every coordinate fits a float is folded over the batch, not branched on per
// vertex; false when one does not (its float and those after it are then not to be used).
// Vertex i's position goes to out + i * stride bytes as one unaligned 16-byte store, whose last
// 4 bytes are 0: a WorldVertex's normal[0], which a caller with normals fills afterwards, or the
// next packed record's x, which the next store writes.
bool place_axis_aligned(const Vertex* vertices, std::size_t count, const WorldTransform& transform,
                        bool identity, unsigned char* out, std::size_t stride) {
  const __m128 only_xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
  if (identity) {
    // Spacing 1 and origin 0 (a raw volume's default): 0 + 1 * v is v itself, except that
    // -0 becomes +0, as adding +0.0f makes it. Each coordinate still must be finite.
    const __m128 largest = _mm_set1_ps(std::numeric_limits<float>::max());
    const __m128 sign = _mm_set1_ps(-0.0f);
    __m128 inside = _mm_cmpeq_ps(largest, largest);
    for (std::size_t i = 0; i < count; ++i) {
      __m128 vertex;
      std::memcpy(&vertex, &vertices[i], sizeof vertex);
      vertex = _mm_add_ps(_mm_and_ps(vertex, only_xyz), _mm_setzero_ps());
      inside = _mm_and_ps(inside, _mm_cmple_ps(_mm_andnot_ps(sign, vertex), largest));
      _mm_storeu_ps(reinterpret_cast<float*>(out + i * stride), vertex);
    }
    return _mm_movemask_ps(inside) == 15;
  }
  const __m128d origin_xy = _mm_setr_pd(transform.origin[0], transform.origin[1]);
  const __m128d origin_z = _mm_setr_pd(transform.origin[2], 0.0);
  const __m128d spacing_xy = _mm_setr_pd(transform.spacing[0], transform.spacing[1]);
  const __m128d spacing_z = _mm_setr_pd(transform.spacing[2], 0.0);
  const __m128d largest = _mm_set1_pd(std::numeric_limits<float>::max());
  const __m128d sign = _mm_set1_pd(-0.0);
  __m128d inside = _mm_cmpeq_pd(largest, largest);
  for (std::size_t i = 0; i < count; ++i) {
    __m128 vertex;
    std::memcpy(&vertex, &vertices[i], sizeof vertex);
    vertex = _mm_and_ps(vertex, only_xyz);  // the axis and flag bytes become 0.0f
    const __m128d world_xy = _mm_add_pd(origin_xy, _mm_mul_pd(spacing_xy, _mm_cvtps_pd(vertex)));
    const __m128d world_z =
        _mm_add_pd(origin_z, _mm_mul_pd(spacing_z, _mm_cvtps_pd(_mm_movehl_ps(vertex, vertex))));
    inside = _mm_and_pd(inside, _mm_cmple_pd(_mm_andnot_pd(sign, world_xy), largest));
    inside = _mm_and_pd(inside, _mm_cmple_pd(_mm_andnot_pd(sign, world_z), largest));
    // A double beyond float's range converts by the instruction's rule (an infinity or the
    // largest float, by rounding), not C++'s undefined one, and the batch is then placed again
    // the careful way.
    _mm_storeu_ps(reinterpret_cast<float*>(out + i * stride),
                  _mm_movelh_ps(_mm_cvtpd_ps(world_xy), _mm_cvtpd_ps(world_z)));
  }
  return _mm_movemask_pd(inside) == 3;
}

}  // namespace
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
