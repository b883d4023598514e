#include "write/mesh/corner_placement.h"

#include <cmath>
#include <cstddef>

#include "write/mesh/axis_aligned_placement.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace mvox {

CornerPlacement::CornerPlacement(const WorldTransform& transform) : transform_(transform) {
  plain_sum_ = transform.is_axis_aligned();
  for (int axis = 0; axis < 3; ++axis)
    if (transform.origin[axis] == 0.0 && std::signbit(transform.origin[axis])) plain_sum_ = false;
  identity_ = plain_sum_ && is_identity_placement(transform);
}

bool CornerPlacement::place(const Vertex* vertices, int count, float (*out)[4]) const {
#if defined(__SSE2__)
  if (plain_sum_)  // rows of 16 bytes: x, y, z, 0
    return place_axis_aligned(vertices, static_cast<std::size_t>(count), transform_, identity_,
                              reinterpret_cast<unsigned char*>(out), sizeof out[0]);
  // position()'s sums in its order, lane by lane: world = origin, then += axes[a] * step for
  // a = 0, 1, 2; x and y side by side in one register, z in the low lane of another (its high
  // lane stays 0, which passes the range check and becomes the row's fourth float).
  const WorldTransform& t = transform_;
  const __m128d largest = _mm_set1_pd(kMaxCoordinate);
  const __m128d sign = _mm_set1_pd(-0.0);
  __m128d inside = _mm_cmpeq_pd(largest, largest);
  __m128d axis_xy[3], axis_z[3];
  for (int a = 0; a < 3; ++a) {
    axis_xy[a] = _mm_setr_pd(t.axes[a][0], t.axes[a][1]);
    axis_z[a] = _mm_set_sd(t.axes[a][2]);
  }
  for (int i = 0; i < count; ++i) {
    const double v[3] = {vertices[i].x, vertices[i].y, vertices[i].z};
    __m128d xy = _mm_setr_pd(t.origin[0], t.origin[1]), z = _mm_set_sd(t.origin[2]);
    for (int a = 0; a < 3; ++a) {
      const __m128d step = _mm_set1_pd(t.spacing[a] * v[a]);
      xy = _mm_add_pd(xy, _mm_mul_pd(axis_xy[a], step));
      z = _mm_add_sd(z, _mm_mul_sd(axis_z[a], step));
    }
    inside = _mm_and_pd(inside, _mm_cmple_pd(_mm_andnot_pd(sign, xy), largest));
    inside = _mm_and_pd(inside, _mm_cmple_pd(_mm_andnot_pd(sign, z), largest));
    // Beyond float's range the conversion follows the instruction's rule (an infinity or the
    // largest float, by rounding), not C++'s undefined one, and the caller does not use it.
    _mm_storeu_ps(out[i], _mm_movelh_ps(_mm_cvtpd_ps(xy), _mm_cvtpd_ps(z)));
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
