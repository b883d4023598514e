#pragma once
// Streams the engine's mesh into a PLY file (docs/design.md section 4), never holding it in memory.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "write/mesh/float_texts.h"
#include "write/mesh/mesh_writer.h"
#include "write/output_file.h"
#include "write/scratch_file.h"

namespace mvox {

enum class PlyFormat : std::uint8_t { binary_little_endian, ascii };

// The shared options (placement, comment lines, normals, --triangulate) and PLY's encoding.
struct PlyWriterOptions : MeshWriterOptions {
  PlyFormat format = PlyFormat::binary_little_endian;
};

// A MeshWriter for PLY:
//   element vertex N: property float x, y, z (and nx, ny, nz with options.normals)
//   element face M:   property list uchar int vertex_indices (uint above 2^31 vertices; at
//                     most 2^32 vertices, beyond which PLY's 32-bit lists cannot reach)
// N and M are known only at the end, so vertices go into the output (an OutputFile temporary)
// after a header area reserved for the largest possible counts, and faces into a ScratchFile in
// the same directory. finish() appends the faces, writes the real header into the reserved area
// (padded to its exact size with a "comment" line of spaces just before end_header) and commits.
// For an output that cannot be overwritten (standard output, a pipe) the vertices wait in a
// ScratchFile too, and the file is written in order by finish(). Memory: two write buffers and a
// copy buffer (about 3 MiB), and for ASCII the texts of recent floats (float_texts.h, 192 KiB),
// whatever the mesh size.
class PlyWriter final : public MeshWriter {
 public:
  // Creates the temporary files. Throws mvox::Error (e.g. "out/mesh.ply: cannot create file:
  // No such file or directory", or an invalid option).
  explicit PlyWriter(const std::string& path, PlyWriterOptions options = {});

  const std::string& subject() const override { return out_.subject(); }
  OutputFile* output_file() override { return &out_; }

  // The header of a file written to a regular target, with these counts: the head of a mesh
  // written in parts (mesh_file_head).
  static std::string head(const PlyWriterOptions& options, std::uint64_t vertex_count,
                          std::uint64_t face_count);
  std::uint64_t part_face_bytes() const override { return part_face_bytes_; }
  // The most vertices 32-bit index lists reach, and why no more.
  static constexpr VertexLimit kVertexLimit = {
      std::uint64_t{1} << 32,
      "PLY's 32-bit index lists cannot address; write OBJ, whose indices have no limit"};
  VertexLimit vertex_limit() const override { return kVertexLimit; }

  // Bytes of the header area for these options (binary and ASCII alike), which is also the
  // offset of the first vertex in a file written to a regular target.
  static std::size_t reserved_header_bytes(const PlyWriterOptions& options);

  // ASCII only: its vertex lines formatted by slab workers.
  std::unique_ptr<VertexTextFormatter> vertex_text_formatter() const override;
  // VertexTextFormatter::most_bytes_per_vertex() of the ASCII formatter, with or without
  // normals.
  static std::size_t most_vertex_text_bytes(bool normals);

 private:
  void write_vertices(const WorldVertex* vertices, std::size_t vertex_count) override;
  void write_faces(const Polygon* faces, std::size_t face_count,
                   std::uint32_t index_offset) override;
  void write_formatted_vertices(const unsigned char* records, std::size_t bytes) override;
  unsigned char* reserve_positions(std::size_t count) override;
  void commit_positions(std::size_t count) override;
  void complete_file() override;
  template <class Sink>
  void write_vertices_to(Sink& sink, const WorldVertex* vertices, std::size_t vertex_count);

  PlyFormat format_;
  OutputFile out_;
  std::optional<ScratchFile> vertex_spool_;  // only when out_ cannot be overwritten
  ScratchFile faces_;
  std::optional<FloatTexts> texts_;  // ASCII only
  std::uint64_t part_face_bytes_ = 0;
};

}  // namespace mvox
