#pragma once
// Streams the engine's mesh into a binary STL file: triangles with their own vertices and a face
// normal each, the format 3-D printing and CAD tools read.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "write/mesh/face_formatter.h"
#include "write/mesh/mesh_writer.h"
#include "write/mesh/stl_triangle_records.h"
#include "write/output_file.h"
#include "write/scratch_file.h"

namespace mvox {

// A MeshWriter for binary STL (little-endian):
//   80-byte header: the first comment line (cut to 80 bytes, padded with spaces), never starting
//                   with "solid", which would make readers take the file for ASCII STL
//   uint32 triangle count
//   per triangle, 50 bytes: float normal[3], float vertex[3][3], uint16 attribute (0)
// STL always triangulates (polygon_triangulation.h), and its vertices are written per triangle,
// so it needs the engine's polygons by value (EngineOptions::polygon_geometry). The normal is the
// unit normal of the written vertices, by the right-hand rule (outward); (0, 0, 0) for a triangle
// whose float vertices have no area. STL has no vertex normals, so options.normals is refused.
// The count is known only at the end: written into its place in the temporary then, or, for an
// output that cannot be overwritten (standard output, a pipe), the triangles wait in a
// ScratchFile and the file is written in order. Memory: two write buffers, whatever the mesh.
class StlWriter final : public MeshWriter {
 public:
  static constexpr std::size_t kHeaderBytes = 80;
  // A polygon of kMaxPolygonVertices corners is split into that many less two triangles.
  static constexpr std::size_t kMostBytesPerPolygon = kMostStlBytesPerPolygon;

  // Creates the temporary file. Throws mvox::Error.
  explicit StlWriter(const std::string& path, const MeshWriterOptions& options = {});

  const std::string& subject() const override { return out_.subject(); }
  OutputFile* output_file() override { return &out_; }
  bool writes_vertex_records() const override { return false; }
  std::unique_ptr<FaceFormatter> face_formatter() const override;

  // The 80 header bytes for these options.
  static std::string header(const MeshWriterOptions& options);
  // The header and the triangle count: the head of a mesh written in parts (mesh_file_head).
  // Throws mvox::Error for more triangles than 32 bits count.
  static std::string head(const MeshWriterOptions& options, std::uint64_t triangle_count);

 private:
  void write_vertices(const WorldVertex* vertices, std::size_t vertex_count) override;
  // Never called: the triangle records are MeshWriter's, made from the polygons' geometry.
  void write_faces(const Polygon* faces, std::size_t face_count,
                   std::uint32_t index_offset) override;
  unsigned char* reserve_triangle_records(std::size_t bytes) override;
  void commit_triangle_records(std::size_t bytes, std::size_t triangle_count) override;
  void complete_file() override;
  void write_formatted_faces(const unsigned char* records, std::size_t bytes,
                             std::size_t face_count) override;
  // Throws unless `face_count` more triangles stay within STL's 32-bit count.
  void check_triangle_room(std::size_t face_count) const;

  OutputFile out_;
  std::optional<ScratchFile> spool_;  // only when out_ cannot be overwritten
};

}  // namespace mvox
