#pragma once
// One rank's part of a binary PLY or STL file that the ranks of mvox-mpi write in place: the
// records PlyWriter and StlWriter write (write/mesh/binary_records.h for PLY's, MeshWriter's
// make_stl_triangle_records for STL's, write/mesh/stl_triangle_records.h), straight into the shared
// file at offsets that the counting pass gives before anything is written
// (distributed_mesh_job.h). PLY's vertex records go into one stream and its face records into
// another; STL's triangles into one. Nothing is written anywhere else: no part file, no copy.
#include <cstdint>
#include <string>

#include "mpi/mpi_file_stream.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {

class PlacedPartWriter final : public MeshWriter {
 public:
  // Whether parts of `format` can be written in place: their sizes follow from the counts
  // (binary PLY and STL; not ASCII PLY or OBJ, whose numbers take as many digits as they need).
  static bool places(MeshFormat format) {
    return format == MeshFormat::ply || format == MeshFormat::stl;
  }
  // The memory it takes: its two streams' buffers and MeshWriter's batches.
  static std::uint64_t working_bytes();

  // `options.part` must be set. `faces` is unused for STL. Both streams are borrowed. Throws
  // mvox::Error for options the format refuses, as the file writers do.
  PlacedPartWriter(MeshFormat format, const MeshWriterOptions& options, MpiFileStream& vertices,
                   MpiFileStream& faces, std::string subject);

  const std::string& subject() const override { return subject_; }
  OutputFile* output_file() override { return nullptr; }
  // Bytes written into each stream so far.
  std::uint64_t vertex_bytes() const { return vertices_.bytes_written(); }
  std::uint64_t face_bytes() const { return stl_ ? 0 : faces_.bytes_written(); }

 private:
  VertexLimit vertex_limit() const override;
  void write_vertices(const WorldVertex* vertices, std::size_t vertex_count) override;
  void write_faces(const Polygon* faces, std::size_t face_count,
                   std::uint32_t index_offset) override;
  unsigned char* reserve_triangle_records(std::size_t bytes) override;
  void commit_triangle_records(std::size_t bytes, std::size_t triangle_count) override;
  void complete_file() override;

  bool stl_;
  MpiFileStream& vertices_;  // STL: the triangles
  MpiFileStream& faces_;
  std::string subject_;
};

}  // namespace mvox
