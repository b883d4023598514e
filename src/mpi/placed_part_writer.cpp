#include "mpi/placed_part_writer.h"

#include <utility>

#include "error.h"
#include "write/mesh/binary_records.h"
#include "write/mesh/ply_writer.h"

namespace mvox {
namespace {

const MeshWriterOptions& checked(MeshFormat format, const MeshWriterOptions& options) {
  if (!PlacedPartWriter::places(format))
    throw Error(mesh_format_name(format), "internal error: parts of this format are not placed");
  if (!options.part) throw Error(mesh_format_name(format), "internal error: not a part");
  // StlWriter's refusal, word for word.
  if (format == MeshFormat::stl && options.writes_normals())
    throw Error("--normals", "STL has face normals only; write PLY or OBJ for vertex normals");
  return options;
}

}  // namespace

std::uint64_t PlacedPartWriter::working_bytes() {
  return 2 * BufferedWriter::kBufferBytes + kMeshWriterBatchBytes;
}

PlacedPartWriter::PlacedPartWriter(MeshFormat format, const MeshWriterOptions& options,
                                   MpiFileStream& vertices, MpiFileStream& faces,
                                   std::string subject)
    : MeshWriter(checked(format, options),
                 format == MeshFormat::stl ? Faces::as_triangles : Faces::as_polygons,
                 format == MeshFormat::stl ? Positions::needed : Positions::not_needed),
      stl_(format == MeshFormat::stl),
      vertices_(vertices),
      faces_(faces),
      subject_(std::move(subject)) {}

MeshWriter::VertexLimit PlacedPartWriter::vertex_limit() const {
  return stl_ ? MeshWriter::vertex_limit() : PlyWriter::kVertexLimit;
}

void PlacedPartWriter::write_vertices(const WorldVertex* vertices, std::size_t vertex_count) {
  // STL writes each triangle's vertices with it.
  if (!stl_) put_ply_vertices(vertices_, vertices, vertex_count, options().writes_normals());
}

void PlacedPartWriter::write_faces(const Polygon* faces, std::size_t face_count,
                                   std::uint32_t index_offset) {
  if (stl_) throw Error(subject_, "internal error: STL faces without their geometry");
  put_ply_faces(faces_, faces, face_count, index_offset, subject_);
}

unsigned char* PlacedPartWriter::reserve_triangle_records(std::size_t bytes) {
  if (!stl_) return MeshWriter::reserve_triangle_records(bytes);
  return reinterpret_cast<unsigned char*>(vertices_.reserve(bytes));
}

void PlacedPartWriter::commit_triangle_records(std::size_t bytes, std::size_t triangle_count) {
  if (!stl_) MeshWriter::commit_triangle_records(bytes, triangle_count);
  vertices_.commit(bytes);
}

void PlacedPartWriter::complete_file() {
  vertices_.flush();
  if (!stl_) faces_.flush();
}

}  // namespace mvox
