#pragma once
// Streams the engine's mesh into a Wavefront OBJ file, in the engine's own order: no counts in
// a header, so nothing waits in a spool and memory does not grow with the mesh.
#include <cstddef>
#include <string>

#include "write/mesh/float_texts.h"
#include "write/mesh/mesh_writer.h"
#include "write/output_file.h"

namespace mvox {

// A MeshWriter for OBJ (text):
//   # COMMENT                one line per comment, first
//   v X Y Z                  one per vertex, as each vertex batch arrives
//   vn NX NY NZ              after its "v" line, with options.normals
//   f I J K ...              one per face, as each polygon batch arrives; 1-based indices, or
//   f I//I J//J K//K ...     with normals (vertex I has normal I)
// The engine sends a polygon's vertices before the polygon, so every face follows the lines of
// the vertices it uses. Numbers are the shortest text that reads back to the same float.
// Memory: the file's buffers and the texts of recent floats (float_texts.h, 192 KiB), whatever
// the mesh size.
class ObjWriter final : public MeshWriter {
 public:
  // Creates the temporary file and writes the comments. Throws mvox::Error.
  explicit ObjWriter(const std::string& path, const MeshWriterOptions& options = {});

  const std::string& subject() const override { return out_.subject(); }
  OutputFile* output_file() override { return &out_; }

  // The comment lines: the head of a mesh written in parts (mesh_file_head).
  static std::string head(const MeshWriterOptions& options);

  std::unique_ptr<VertexTextFormatter> vertex_text_formatter() const override;
  // VertexTextFormatter::most_bytes_per_vertex() of its formatter, with or without normals.
  static std::size_t most_vertex_text_bytes(bool normals);

 private:
  void write_vertices(const WorldVertex* vertices, std::size_t vertex_count) override;
  void write_faces(const Polygon* faces, std::size_t face_count,
                   std::uint32_t index_offset) override;
  void write_formatted_vertices(const unsigned char* records, std::size_t bytes) override;
  void complete_file() override;

  OutputFile out_;
  FloatTexts texts_;
};

}  // namespace mvox
