#pragma once
// The records of binary PLY and STL, and their sizes: shared by the file writers (ply_writer.h,
// stl_writer.h) and by mvox-mpi's writer of parts in place (mpi/placed_part_writer.h), which
// must write the very bytes the file writers write, at offsets worked out from the counts alone.
//
// Records are formatted straight into a sink's buffer, a run at a time: a write call per record
// cost more than the formatting. A Sink has
//   void* reserve(std::size_t bytes)   room for `bytes` (at most BufferedWriter::kBufferBytes)
//   void commit(std::size_t bytes)     appends the `bytes` written there
// as OutputFile and ScratchFile have.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "error.h"
#include "mvox/mesh.h"
#include "write/buffered_writer.h"
#include "write/mesh/little_endian.h"
#include "write/mesh/mesh_writer.h"
#include "write/mesh/vertex_placement.h"

namespace mvox {

// Binary PLY: a vertex is x, y, z (and nx, ny, nz) as floats; a face, a count byte and its
// indices as 32-bit integers.
constexpr std::size_t ply_vertex_record_bytes(bool normals) { return normals ? 24 : 12; }
constexpr std::size_t ply_face_record_bytes(int corners) {
  return 1 + 4 * static_cast<std::size_t>(corners);
}
// Binary STL: a triangle is its normal and three vertices as floats, and a 16-bit attribute.
constexpr std::size_t kStlTriangleBytes = 50;

template <class Sink>
void put_ply_vertices(Sink& sink, const WorldVertex* vertices, std::size_t vertex_count,
                      bool normals) {
  const std::size_t record_bytes = ply_vertex_record_bytes(normals);
  const std::size_t per_run = BufferedWriter::kBufferBytes / record_bytes;
  for (std::size_t first = 0; first < vertex_count; first += per_run) {
    const std::size_t count = std::min(per_run, vertex_count - first);
    auto* out = static_cast<unsigned char*>(static_cast<void*>(sink.reserve(count * record_bytes)));
    for (std::size_t i = first; i < first + count; ++i) {
      const WorldVertex& vertex = vertices[i];
      for (int axis = 0; axis < 3; ++axis) out = store_le_float(out, vertex.position[axis]);
      if (normals)
        for (int axis = 0; axis < 3; ++axis) out = store_le_float(out, vertex.normal[axis]);
    }
    sink.commit(count * record_bytes);
  }
}

// Each index plus `index_offset`, modulo 2^32, is written (MeshWriter::write_faces). `subject`
// names the file in the error for a face of more than kMaxPolygonVertices corners, which
// MeshWriter has refused already; checked again so that a record provably fits its run.
template <class Sink>
void put_ply_faces(Sink& sink, const Polygon* faces, std::size_t face_count,
                   std::uint32_t index_offset, const std::string& subject) {
  constexpr std::size_t kLargestRecord = ply_face_record_bytes(kMaxPolygonVertices);
  constexpr std::size_t kPerRun = BufferedWriter::kBufferBytes / kLargestRecord;
  for (std::size_t first = 0; first < face_count; first += kPerRun) {
    const std::size_t count = std::min(kPerRun, face_count - first);
    auto* const start =
        static_cast<unsigned char*>(static_cast<void*>(sink.reserve(count * kLargestRecord)));
    unsigned char* out = start;
    for (std::size_t i = first; i < first + count; ++i) {
      const Polygon& face = faces[i];
      const int corners = face.vertex_count;
      if (corners > kMaxPolygonVertices) throw Error(subject, "internal error: face too large");
      *out = static_cast<unsigned char>(corners);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
      // All seven index slots, whatever the count, as two overlapping runs of four (slots 0-3
      // and 3-6): fixed sizes, which the compiler makes two vector loads, adds and stores, where
      // a loop of `corners` stores cost more than the rest of the function. The slots past this
      // face's corners hold whatever the polygon's maker put there (the engine writes every
      // slot) and land inside its largest record's room: the next record overwrites them, or
      // they stay past the bytes committed.
      static_assert(kMaxPolygonVertices == 7, "two runs of four index slots");
      std::uint32_t first_four[4], last_four[4];
      for (int k = 0; k < 4; ++k) first_four[k] = face.vertices[k] + index_offset;
      for (int k = 0; k < 4; ++k) last_four[k] = face.vertices[3 + k] + index_offset;
      std::memcpy(out + 1, first_four, sizeof first_four);
      std::memcpy(out + 1 + 12, last_four, sizeof last_four);
      out += ply_face_record_bytes(corners);
#else
      ++out;
      for (int k = 0; k < corners; ++k) out = store_le32(out, face.vertices[k] + index_offset);
#endif
    }
    sink.commit(static_cast<std::size_t>(out - start));
  }
}

// The unit normal of the triangle as written (float vertices, computed in double), by the
// right-hand rule; zero when the rounded vertices have no area.
inline void stl_face_normal(const float (*p)[3], float normal[3]) {
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

// stl_face_normal() of two triangles at once, one in each lane of SSE2's doubles: the same
// operations in the same order, so the same floats. The square root and the three divisions,
// whose latency bounds the scalar version, are then shared by the pair.
#if defined(__SSE2__)
inline void stl_face_normals(const float (*p)[3], const float (*q)[3], float normal_p[3],
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

// `faces` must be triangles, each with its world positions in `positions`.
template <class Sink>
void put_stl_triangles(Sink& sink, const Polygon* faces, const FacePositions* positions,
                       std::size_t face_count, const std::string& subject) {
  constexpr std::size_t kPerRun = BufferedWriter::kBufferBytes / kStlTriangleBytes;
  for (std::size_t first = 0; first < face_count; first += kPerRun) {
    const std::size_t count = std::min(kPerRun, face_count - first);
    auto* end =
        static_cast<unsigned char*>(static_cast<void*>(sink.reserve(count * kStlTriangleBytes)));
    auto put = [&](const float(*p)[3], const float normal[3]) {
      for (int axis = 0; axis < 3; ++axis) end = store_le_float(end, normal[axis]);
      for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis) end = store_le_float(end, p[k][axis]);
      *end++ = 0;  // attribute byte count: 0, as nearly every reader expects
      *end++ = 0;
    };
    for (std::size_t i = first; i < first + count; ++i)
      if (faces[i].vertex_count != 3)
        throw Error(subject, "internal error: an STL face with " +
                                 std::to_string(faces[i].vertex_count) + " vertices");
    std::size_t i = first;
#if defined(__SSE2__)
    for (; i + 1 < first + count; i += 2) {
      float normal_p[3], normal_q[3];
      stl_face_normals(positions[i].xyz, positions[i + 1].xyz, normal_p, normal_q);
      put(positions[i].xyz, normal_p);
      put(positions[i + 1].xyz, normal_q);
    }
#endif
    for (; i < first + count; ++i) {
      float normal[3];
      stl_face_normal(positions[i].xyz, normal);
      put(positions[i].xyz, normal);
    }
    sink.commit(count * kStlTriangleBytes);
  }
}

}  // namespace mvox
