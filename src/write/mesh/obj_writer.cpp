#include "write/mesh/obj_writer.h"

#include <algorithm>
#include <charconv>
#include <cstring>

#include "write/buffered_writer.h"
#include "write/mesh/text_line_runs.h"
#include "write/mesh/vertex_text_formatter.h"

namespace mvox {
namespace {

// Vertex lines are written a run at a time straight into the file's buffer: "v", then per
// coordinate a space and its text (FloatTexts::put may write kRoom bytes), and the newline;
// the same with "vn" after it for normals.
constexpr std::size_t kMostLineBytes = 2 + 3 * (1 + FloatTexts::kRoom) + 1;

char* put_floats(char* out, const char* keyword, const float* values, FloatTexts& texts) {
  while (*keyword) *out++ = *keyword++;
  for (int i = 0; i < 3; ++i) {
    *out++ = ' ';
    out = texts.put(out, values[i]);
  }
  *out++ = '\n';
  return out;
}

// The lines of `vertex_count` vertices into `sink` (the file, or a slab worker's records), a run
// at a time, straight into its buffer.
template <class Sink>
void put_vertex_lines(Sink& sink, const WorldVertex* vertices, std::size_t vertex_count,
                      bool with_normals, FloatTexts& texts) {
  put_line_runs(sink, vertex_count, ObjWriter::most_vertex_text_bytes(with_normals),
                [&](char* out, std::size_t i) {
                  out = put_floats(out, "v", vertices[i].position, texts);
                  return with_normals ? put_floats(out, "vn", vertices[i].normal, texts) : out;
                });
}

// "f", then per vertex a space and "I" or "I//I" with I of at most 20 digits, and the newline.
constexpr std::size_t kMostFaceBytes = 1 + kMaxPolygonVertices * (1 + 20 + 2 + 20) + 1;

}  // namespace

std::size_t ObjWriter::most_vertex_text_bytes(bool normals) {
  return (normals ? 2 : 1) * kMostLineBytes;
}

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
  put_vertex_lines(out_, vertices, vertex_count, options().writes_normals(), texts_);
}

std::unique_ptr<VertexTextFormatter> ObjWriter::vertex_text_formatter() const {
  return std::make_unique<VertexLines>(&put_vertex_lines<FormattedRecords>,
                                       options().writes_normals(),
                                       most_vertex_text_bytes(options().writes_normals()));
}

void ObjWriter::write_formatted_vertices(const unsigned char* records, std::size_t bytes) {
  out_.write(records, bytes);
}

void ObjWriter::write_faces(const Polygon* faces, std::size_t face_count,
                            std::uint32_t index_offset) {
  const bool with_normals = options().writes_normals();
  put_line_runs(out_, face_count, kMostFaceBytes, [&](char* out, std::size_t i) {
    const Polygon& face = faces[i];
    // MeshWriter checked every face; checked again so that the run provably fits its room.
    if (face.vertex_count > kMaxPolygonVertices)
      throw Error(subject(), "internal error: face too large");
    *out++ = 'f';
    for (int k = 0; k < face.vertex_count; ++k) {
      // OBJ counts from 1, in as many digits as the whole index takes (past 2^32 too).
      const std::uint64_t index =
          whole_vertex_index(face.vertices[k] + index_offset, vertices_written()) + 1;
      *out++ = ' ';
      if (!with_normals) {
        out = std::to_chars(out, out + 20, index).ptr;
        continue;
      }
      // "I//I": the digits made once, and copied as all 20 bytes an index has room for, a
      // copy of fixed size that the compiler inlines; the bytes past the digits are
      // overwritten or not committed.
      char digits[20];
      const std::size_t length = static_cast<std::size_t>(
          std::to_chars(digits, digits + sizeof digits, index).ptr - digits);
      std::memcpy(out, digits, sizeof digits);
      out += length;
      *out++ = '/';
      *out++ = '/';
      std::memcpy(out, digits, sizeof digits);
      out += length;
    }
    *out++ = '\n';
    return out;
  });
}

void ObjWriter::complete_file() { out_.seal(); }

}  // namespace mvox
