#include "write/mesh/obj_writer.h"

#include <charconv>
#include <cstring>

namespace mvox {
namespace {

char* put_floats(char* out, char* end, const char* keyword, const float* values) {
  while (*keyword) *out++ = *keyword++;
  for (int i = 0; i < 3; ++i) {
    *out++ = ' ';
    out = std::to_chars(out, end, values[i]).ptr;
  }
  *out++ = '\n';
  return out;
}

}  // namespace

std::string ObjWriter::head(const MeshWriterOptions& options) {
  std::string comments;
  for (const std::string& comment : options.comments) comments += "# " + comment + "\n";
  return comments;
}

ObjWriter::ObjWriter(const std::string& path, const MeshWriterOptions& options)
    : MeshWriter(options, Faces::as_polygons, Positions::not_needed), out_(path, options.sync) {
  if (this->options().part) return;  // a part has no comments: they head the whole file
  const std::string comments = head(this->options());
  out_.write(comments.data(), comments.size());
}

void ObjWriter::write_vertices(const WorldVertex* vertices, std::size_t vertex_count) {
  const bool with_normals = options().writes_normals();
  for (std::size_t i = 0; i < vertex_count; ++i) {
    // "vn" and three floats of at most 15 characters each, twice.
    char lines[2 * (2 + 3 * 16 + 1)];
    char* end = put_floats(lines, lines + sizeof lines, "v", vertices[i].position);
    if (with_normals) end = put_floats(end, lines + sizeof lines, "vn", vertices[i].normal);
    out_.write(lines, static_cast<std::size_t>(end - lines));
  }
}

void ObjWriter::write_faces(const Polygon* faces, const FacePositions*, std::size_t face_count,
                           std::uint32_t index_offset) {
  const bool with_normals = options().writes_normals();
  for (std::size_t i = 0; i < face_count; ++i) {
    const Polygon& face = faces[i];
    // "f", then per vertex a space and "I" or "I//I", I of at most 20 digits, and the newline.
    char line[1 + kMaxPolygonVertices * 43 + 1];
    std::size_t used = 0;
    line[used++] = 'f';
    for (int k = 0; k < face.vertex_count; ++k) {
      // OBJ counts from 1, in as many digits as the whole index takes (past 2^32 too).
      char digits[20];
      const std::uint64_t index =
          whole_vertex_index(face.vertices[k] + index_offset, vertices_written()) + 1;
      const std::size_t length = static_cast<std::size_t>(
          std::to_chars(digits, digits + sizeof digits, index).ptr - digits);
      line[used++] = ' ';
      std::memcpy(line + used, digits, length);
      used += length;
      if (with_normals) {
        line[used++] = '/';
        line[used++] = '/';
        std::memcpy(line + used, digits, length);
        used += length;
      }
    }
    line[used++] = '\n';
    out_.write(line, used);
  }
}

void ObjWriter::complete_file() { out_.seal(); }

}  // namespace mvox
