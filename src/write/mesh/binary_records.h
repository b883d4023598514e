#pragma once
// The records of binary PLY and their sizes (STL's, records and size, are in
// stl_triangle_records.h, which this includes): shared by the file writers (ply_writer.h,
// stl_writer.h) and by mvox-mpi's writer of parts in place (mpi/placed_part_writer.h), which must
// write the very bytes the file writers write, at offsets worked out from the counts alone.
//
// Records are formatted straight into a sink's buffer, a run at a time: a write call per record
// cost more than the formatting. A Sink has
//   void* reserve(std::size_t bytes)   room for `bytes` (at most BufferedWriter::kBufferBytes)
//   void commit(std::size_t bytes)     appends the `bytes` written there
// as OutputFile and ScratchFile have.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "error.h"
#include "mvox/mesh.h"
#include "write/buffered_writer.h"
#include "write/mesh/little_endian.h"
#include "write/mesh/stl_triangle_records.h"
#include "write/mesh/vertex_placement.h"

namespace mvox {

// Binary PLY: a vertex is x, y, z (and nx, ny, nz) as floats; a face, a count byte and its
// indices as 32-bit integers.
constexpr std::size_t ply_vertex_record_bytes(bool normals) { return normals ? 24 : 12; }
constexpr std::size_t ply_face_record_bytes(int corners) {
  return 1 + 4 * static_cast<std::size_t>(corners);
}

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

}  // namespace mvox
