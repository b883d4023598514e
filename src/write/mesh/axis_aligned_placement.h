#pragma once
// World positions on identity axes for a whole batch at once, with SSE2: origin + spacing * v
// per axis in double, rounded to float, as WorldTransform::axis_aligned_position() computes it.
// Shared by VertexPlacement (every vertex of a written mesh) and CornerPlacement (the corners of
// STL's triangles), which store the positions with different strides.
#include <cstddef>
#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "mvox/mesh.h"
#include "write/mesh/world_transform.h"

namespace mvox {

// Spacing 1 and origin +0 (a raw volume's default): on identity axes every position is then its
// vertex itself, but for -0, which becomes +0. An origin of -0 is not: -0 + 1 * -0 is -0.
bool is_identity_placement(const WorldTransform& transform);

#if defined(__SSE2__)
static_assert(sizeof(Vertex) == 16 && offsetof(Vertex, x) == 0 && offsetof(Vertex, y) == 4 &&
                  offsetof(Vertex, z) == 8,
              "a vertex is x, y, z and four bytes more: one 16-byte load");

// `transform` must have identity axes; `identity` is is_identity_placement(transform). Vertex
// i's position goes to out + i * stride bytes as one unaligned 16-byte store, whose last 4 bytes
// are 0: a WorldVertex's normal[0], which a caller with normals fills afterwards, the next
// packed record's x, which the next store writes, or a corner row's fourth float. Whether every
// coordinate fits a float is folded over the batch, not branched on per vertex; false when one
// does not (its float and those after it are then not to be used). Inline, so that each
// caller's stride is a constant in its loop.
inline bool place_axis_aligned(const Vertex* vertices, std::size_t count,
                               const WorldTransform& transform, bool identity, unsigned char* out,
                               std::size_t stride) {
  const __m128 only_xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
  if (identity) {
    // 0 + 1 * v is v itself, in float (the same two roundings give the same float), except
    // that -0 becomes +0, as adding +0.0f makes it. Each coordinate still must be finite.
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
  // x and y in one register, z in another.
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
    // largest float, by rounding), not C++'s undefined one, and the caller does not use it.
    _mm_storeu_ps(reinterpret_cast<float*>(out + i * stride),
                  _mm_movelh_ps(_mm_cvtpd_ps(world_xy), _mm_cvtpd_ps(world_z)));
  }
  return _mm_movemask_pd(inside) == 3;
}
#endif

}  // namespace mvox
