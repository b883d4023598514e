#include "write/mesh/stl_triangle_records.h"

#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "write/mesh/little_endian.h"
#include "write/mesh/polygon_triangulation.h"

namespace mvox {
namespace {

// Where a record's parts start.
constexpr std::size_t kNormalAt = 0;
constexpr std::size_t kCornersAt = 12;
constexpr std::size_t kAttributeAt = 48;

// A triangle's corners and attribute into its record; the normal comes later (fill_normals).
inline void put_corners(unsigned char* record, const float* a, const float* b, const float* c) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  // A corner row is x, y, z, 0 (CornerPlacement::place): each goes out as one 16-byte store, in
  // order, so that each overwrites the previous one's 0. The last one's 0 is the attribute and
  // two bytes of the next record's normal, which fill_normals() writes later.
  static_assert(kCornersAt + 3 * 12 == kAttributeAt &&
                    kAttributeAt + 4 - kStlTriangleBytes == kStlRecordSlack,
                "16-byte corner stores end 2 bytes past the record");
  std::memcpy(record + kCornersAt, a, 16);
  std::memcpy(record + kCornersAt + 12, b, 16);
  std::memcpy(record + kCornersAt + 24, c, 16);
#else
  unsigned char* out = record + kCornersAt;
  for (const float* corner : {a, b, c})
    for (int axis = 0; axis < 3; ++axis) out = store_le_float(out, corner[axis]);
  out[0] = out[1] = 0;  // the attribute, 0, as nearly every reader expects
#endif
}

inline void load_corners(const unsigned char* record, float (*p)[3]) {
  const unsigned char* in = record + kCornersAt;
  for (int k = 0; k < 3; ++k)
    for (int axis = 0; axis < 3; ++axis, in += 4) p[k][axis] = load_le_float(in);
}

inline void put_normal(unsigned char* record, const float normal[3]) {
  unsigned char* out = record + kNormalAt;
  for (int axis = 0; axis < 3; ++axis) out = store_le_float(out, normal[axis]);
}

// Each record's normal, from the corners as written: two at a time where SSE2 has the lanes.
void fill_normals(unsigned char* records, std::size_t count) {
  std::size_t i = 0;
#if defined(__SSE2__)
  for (; i + 1 < count; i += 2) {
    unsigned char* first = records + i * kStlTriangleBytes;
    unsigned char* second = first + kStlTriangleBytes;
    float p[3][3], q[3][3], normal_p[3], normal_q[3];
    load_corners(first, p);
    load_corners(second, q);
    stl_face_normals(p, q, normal_p, normal_q);
    put_normal(first, normal_p);
    put_normal(second, normal_q);
  }
#endif
  for (; i < count; ++i) {
    unsigned char* record = records + i * kStlTriangleBytes;
    float p[3][3], normal[3];
    load_corners(record, p);
    stl_face_normal(p, normal);
    put_normal(record, normal);
  }
}

}  // namespace

StlRecordsMade make_stl_triangle_records(const CornerPlacement& placement, bool mirrors,
                                         const PolygonGeometry* polygons, std::size_t count,
                                         unsigned char* out) {
  StlRecordsMade made;
  unsigned char* record = out;
  for (; made.polygons < count; ++made.polygons) {
    const PolygonGeometry& polygon = polygons[made.polygons];
    const int n = polygon.vertex_count;
    float corners[kMaxPolygonVertices][4];
    if (n < 3 || n > kMaxPolygonVertices || !placement.place(polygon.vertices, n, corners)) break;
    const int apex = n == 3 ? 0 : fan_apex(polygon);
    if (apex < 0) break;
    // The fan's triangles (apex, b, b + 1), b = apex + 1 .. apex + n - 2, modulo n.
    int b = apex + 1 < n ? apex + 1 : 0;
    for (int t = 0; t < n - 2; ++t) {
      const int c = b + 1 < n ? b + 1 : 0;
      // Walking (apex, b, c) backwards from the first corner gives (apex, c, b).
      put_corners(record, corners[apex], corners[mirrors ? c : b], corners[mirrors ? b : c]);
      record += kStlTriangleBytes;
      b = c;
    }
    made.triangles += static_cast<std::size_t>(n - 2);
  }
  fill_normals(out, made.triangles);
  return made;
}

void stl_face_normal(const float (*p)[3], float normal[3]) {
  double u[3], v[3];
  for (int i = 0; i < 3; ++i) {
    u[i] = double{p[1][i]} - p[0][i];
    v[i] = double{p[2][i]} - p[0][i];
  }
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int i = 0; i < 3; ++i) normal[i] = length > 0.0 ? static_cast<float>(n[i] / length) : 0.0f;
}

#if defined(__SSE2__)
void stl_face_normals(const float (*p)[3], const float (*q)[3], float normal_p[3],
                      float normal_q[3]) {
  __m128d u[3], v[3];
  for (int i = 0; i < 3; ++i) {
    const __m128d first = _mm_setr_pd(p[0][i], q[0][i]);
    u[i] = _mm_sub_pd(_mm_setr_pd(p[1][i], q[1][i]), first);
    v[i] = _mm_sub_pd(_mm_setr_pd(p[2][i], q[2][i]), first);
  }
  const __m128d n[3] = {_mm_sub_pd(_mm_mul_pd(u[1], v[2]), _mm_mul_pd(u[2], v[1])),
                        _mm_sub_pd(_mm_mul_pd(u[2], v[0]), _mm_mul_pd(u[0], v[2])),
                        _mm_sub_pd(_mm_mul_pd(u[0], v[1]), _mm_mul_pd(u[1], v[0]))};
  const __m128d length = _mm_sqrt_pd(_mm_add_pd(
      _mm_add_pd(_mm_mul_pd(n[0], n[0]), _mm_mul_pd(n[1], n[1])), _mm_mul_pd(n[2], n[2])));
  // Where the rounded vertices have no area the normal is 0 (the quotient, 0/0, is dropped).
  const __m128d has_area = _mm_cmpgt_pd(length, _mm_setzero_pd());
  for (int i = 0; i < 3; ++i) {
    const __m128 unit = _mm_cvtpd_ps(_mm_and_pd(_mm_div_pd(n[i], length), has_area));
    normal_p[i] = _mm_cvtss_f32(unit);
    normal_q[i] = _mm_cvtss_f32(_mm_shuffle_ps(unit, unit, _MM_SHUFFLE(1, 1, 1, 1)));
  }
}
#endif

}  // namespace mvox
