#include "write/mesh/corner_placement.h"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace mvox {

CornerPlacement::CornerPlacement(const WorldTransform& transform) : transform_(transform) {
  plain_sum_ = transform.is_axis_aligned();
  identity_ = plain_sum_;
  for (int axis = 0; axis < 3; ++axis) {
    if (transform.origin[axis] == 0.0 && std::signbit(transform.origin[axis])) plain_sum_ = false;
    if (transform.spacing[axis] != 1.0 || transform.origin[axis] != 0.0) identity_ = false;
  }
  identity_ = identity_ && plain_sum_;
}

#if defined(__SSE2__)
static_assert(sizeof(Vertex) == 16 && offsetof(Vertex, x) == 0 && offsetof(Vertex, y) == 4 &&
                  offsetof(Vertex, z) == 8,
              "a vertex is x, y, z and four bytes more: one 16-byte load");
#endif

bool CornerPlacement::place(const Vertex* vertices, int count, float (*out)[4]) const {
#if defined(__SSE2__)
  // The world's x and y side by side in one register, z in the low lane of another (its high
  // lane stays 0, which passes the range check).
  const WorldTransform& t = transform_;
  const __m128d origin_xy = _mm_setr_pd(t.origin[0], t.origin[1]);
  const __m128d origin_z = _mm_set_sd(t.origin[2]);
  const __m128d largest = _mm_set1_pd(kMaxCoordinate);
  const __m128d sign = _mm_set1_pd(-0.0);
  __m128d inside = _mm_cmpeq_pd(largest, largest);
  auto keep = [&](int i, __m128d xy, __m128d z) {
    inside = _mm_and_pd(inside, _mm_cmple_pd(_mm_andnot_pd(sign, xy), largest));
    inside = _mm_and_pd(inside, _mm_cmple_pd(_mm_andnot_pd(sign, z), largest));
    // Beyond float's range the conversion follows the instruction's rule (an infinity or the
    // largest float, by rounding), not C++'s undefined one, and the caller does not use it.
    // z's high lane is 0: the row is x, y, z, 0.
    _mm_storeu_ps(out[i], _mm_movelh_ps(_mm_cvtpd_ps(xy), _mm_cvtpd_ps(z)));
  };
  if (identity_) {
    // v + 0.0f a corner, in floats: what the sums in double round back to. Finite or not is
    // folded over the corners.
    const __m128 only_xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    const __m128 largest_float = _mm_set1_ps(std::numeric_limits<float>::max());
    const __m128 float_sign = _mm_set1_ps(-0.0f);
    __m128 finite = _mm_cmpeq_ps(largest_float, largest_float);
    for (int i = 0; i < count; ++i) {
      __m128 v;
      std::memcpy(&v, &vertices[i], sizeof v);
      v = _mm_add_ps(_mm_and_ps(v, only_xyz), _mm_setzero_ps());
      finite = _mm_and_ps(finite, _mm_cmple_ps(_mm_andnot_ps(float_sign, v), largest_float));
      _mm_storeu_ps(out[i], v);
    }
    return _mm_movemask_ps(finite) == 15;
  }
  if (plain_sum_) {
    // origin + spacing * v, as WorldTransform::axis_aligned_position.
    const __m128d spacing_xy = _mm_setr_pd(t.spacing[0], t.spacing[1]);
    const __m128d spacing_z = _mm_set_sd(t.spacing[2]);
    for (int i = 0; i < count; ++i) {
      const __m128d v_xy = _mm_setr_pd(vertices[i].x, vertices[i].y);
      const __m128d v_z = _mm_set_sd(vertices[i].z);
      keep(i, _mm_add_pd(origin_xy, _mm_mul_pd(spacing_xy, v_xy)),
           _mm_add_sd(origin_z, _mm_mul_sd(spacing_z, v_z)));
    }
    return _mm_movemask_pd(inside) == 3;
  }
  // position()'s sums in its order, lane by lane: world = origin, then += axes[a] * step for
  // a = 0, 1, 2.
  __m128d axis_xy[3], axis_z[3];
  for (int a = 0; a < 3; ++a) {
    axis_xy[a] = _mm_setr_pd(t.axes[a][0], t.axes[a][1]);
    axis_z[a] = _mm_set_sd(t.axes[a][2]);
  }
  for (int i = 0; i < count; ++i) {
    const double v[3] = {vertices[i].x, vertices[i].y, vertices[i].z};
    __m128d xy = origin_xy, z = origin_z;
    for (int a = 0; a < 3; ++a) {
      const __m128d step = _mm_set1_pd(t.spacing[a] * v[a]);
      xy = _mm_add_pd(xy, _mm_mul_pd(axis_xy[a], step));
      z = _mm_add_sd(z, _mm_mul_sd(axis_z[a], step));
    }
    keep(i, xy, z);
  }
  return _mm_movemask_pd(inside) == 3;
#else
  for (int i = 0; i < count; ++i) {
    const Vector3d world = transform_.position(vertices[i].x, vertices[i].y, vertices[i].z);
    for (int axis = 0; axis < 3; ++axis) {
      if (!(std::fabs(world[axis]) <= kMaxCoordinate)) return false;
      out[i][axis] = static_cast<float>(world[axis]);
    }
    out[i][3] = 0.0f;
  }
  return true;
#endif
}

}  // namespace mvox
