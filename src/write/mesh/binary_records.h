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
#include <string>

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
      *out++ = static_cast<unsigned char>(corners);
      for (int k = 0; k < corners; ++k) out = store_le32(out, face.vertices[k] + index_offset);
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

// `faces` must be triangles, each with its world positions in `positions`.
template <class Sink>
void put_stl_triangles(Sink& sink, const Polygon* faces, const FacePositions* positions,
                       std::size_t face_count, const std::string& subject) {
  constexpr std::size_t kPerRun = BufferedWriter::kBufferBytes / kStlTriangleBytes;
  for (std::size_t first = 0; first < face_count; first += kPerRun) {
    const std::size_t count = std::min(kPerRun, face_count - first);
    auto* end =
        static_cast<unsigned char*>(static_cast<void*>(sink.reserve(count * kStlTriangleBytes)));
    for (std::size_t i = first; i < first + count; ++i) {
      if (faces[i].vertex_count != 3)
        throw Error(subject, "internal error: an STL face with " +
                                 std::to_string(faces[i].vertex_count) + " vertices");
      const float(*p)[3] = positions[i].xyz;
      float normal[3];
      stl_face_normal(p, normal);
      for (float value : normal) end = store_le_float(end, value);
      for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis) end = store_le_float(end, p[k][axis]);
      *end++ = 0;  // attribute byte count: 0, as nearly every reader expects
      *end++ = 0;
    }
    sink.commit(count * kStlTriangleBytes);
  }
}

}  // namespace mvox
