#include "write/mesh/ply_writer.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <limits>

#include "write/mesh/binary_records.h"
#include "write/mesh/text_line_runs.h"
#include "write/mesh/vertex_text_formatter.h"

namespace mvox {
namespace {

// Counts are reserved at their widest: 20 digits, enough for any 64-bit value.
constexpr std::uint64_t kWidestCount = std::numeric_limits<std::uint64_t>::max();
constexpr char kEndHeader[] = "end_header\n";
constexpr std::size_t kEndHeaderBytes = sizeof kEndHeader - 1;
// The padding line is "comment" followed by at least one space, so it is never empty.
constexpr std::size_t kShortestPaddingBytes = sizeof "comment \n" - 1;

// Signed 32-bit indices, as most readers expect, while they reach every vertex; unsigned up to
// 2^32 vertices (PlyWriter::vertex_limit).
const char* index_type(std::uint64_t vertex_count) {
  return vertex_count <= (std::uint64_t{1} << 31) ? "int" : "uint";
}

// The header without its padding line and end_header.
std::string header_lines(PlyFormat format, const MeshWriterOptions& options,
                         std::uint64_t vertex_count, std::uint64_t face_count,
                         const char* indices) {
  std::string text = "ply\n";
  text += format == PlyFormat::ascii ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n";
  for (const std::string& comment : options.comments) text += "comment " + comment + "\n";
  text += "element vertex " + std::to_string(vertex_count) + "\n";
  text += "property float x\nproperty float y\nproperty float z\n";
  if (options.writes_normals()) text += "property float nx\nproperty float ny\nproperty float nz\n";
  text += "element face " + std::to_string(face_count) + "\n";
  text += std::string("property list uchar ") + indices + " vertex_indices\n";
  return text;
}

// The header as a file written to a regular target has it: padded with spaces in a comment
// line so that it fills the area reserved for the widest counts exactly.
std::string padded_header(PlyFormat format, const MeshWriterOptions& options,
                          std::uint64_t vertex_count, std::uint64_t face_count) {
  // Reserved for the widest counts with "int": "uint" needs one byte more, and comes only with
  // counts of 10 digits, never 20.
  const std::size_t reserved =
      header_lines(format, options, kWidestCount, kWidestCount, "int").size() +
      kShortestPaddingBytes + kEndHeaderBytes;
  std::string header =
      header_lines(format, options, vertex_count, face_count, index_type(vertex_count));
  header += "comment";
  header.append(reserved - header.size() - kEndHeaderBytes - 1, ' ');
  header += '\n';
  header += kEndHeader;
  return header;
}

// ASCII vertex lines into `sink` (the file, a vertex spool or a slab worker's records), a run of
// lines at a time, straight into its buffer.
template <class Sink>
void put_ascii_vertices(Sink& sink, const WorldVertex* vertices, std::size_t vertex_count,
                        bool normals, FloatTexts& texts) {
  const int fields = normals ? 6 : 3;
  put_line_runs(sink, vertex_count, PlyWriter::most_vertex_text_bytes(normals),
                [&](char* out, std::size_t i) {
                  const WorldVertex& vertex = vertices[i];
                  const float written[6] = {vertex.position[0], vertex.position[1],
                                            vertex.position[2], vertex.normal[0],
                                            vertex.normal[1],   vertex.normal[2]};
                  for (int field = 0; field < fields; ++field) {
                    out = texts.put(out, written[field]);
                    *out++ = field + 1 < fields ? ' ' : '\n';
                  }
                  return out;
                });
}

}  // namespace

std::size_t PlyWriter::most_vertex_text_bytes(bool normals) {
  // Each field's text (put() may write FloatTexts::kRoom bytes), followed by a space or the
  // newline.
  return (normals ? 6 : 3) * (FloatTexts::kRoom + 1);
}

std::string PlyWriter::head(const PlyWriterOptions& options, std::uint64_t vertex_count,
                            std::uint64_t face_count) {
  return padded_header(options.format, options, vertex_count, face_count);
}

std::size_t PlyWriter::reserved_header_bytes(const PlyWriterOptions& options) {
  return padded_header(options.format, options, 0, 0).size();
}

PlyWriter::PlyWriter(const std::string& path, PlyWriterOptions options)
    : MeshWriter(options, Faces::as_polygons, Positions::not_needed),
      format_(options.format),
      out_(path, options.sync),
      faces_(out_.scratch_directory(), out_.subject()) {
  if (format_ == PlyFormat::ascii) texts_.emplace();
  if (options.part) {
    // A part has no header: its vertices, then its faces.
  } else if (out_.can_overwrite()) {
    // Placeholder until finish(): the same size as the real header, so nothing moves.
    const std::string placeholder(reserved_header_bytes(options), ' ');
    out_.write(placeholder.data(), placeholder.size());
  } else {
    vertex_spool_.emplace(out_.scratch_directory(), out_.subject());
  }
}

void PlyWriter::write_vertices(const WorldVertex* vertices, std::size_t vertex_count) {
  if (vertex_spool_) {
    write_vertices_to(*vertex_spool_, vertices, vertex_count);
  } else {
    write_vertices_to(out_, vertices, vertex_count);
  }
}

template <class Sink>
void PlyWriter::write_vertices_to(Sink& sink, const WorldVertex* vertices,
                                  std::size_t vertex_count) {
  const bool normals = options().writes_normals();
  if (format_ == PlyFormat::ascii) {
    put_ascii_vertices(sink, vertices, vertex_count, normals, *texts_);
    return;
  }
  put_ply_vertices(sink, vertices, vertex_count, normals);
}

std::unique_ptr<VertexTextFormatter> PlyWriter::vertex_text_formatter() const {
  if (format_ != PlyFormat::ascii) return nullptr;
  return std::make_unique<VertexLines>(&put_ascii_vertices<FormattedRecords>,
                                       options().writes_normals(),
                                       most_vertex_text_bytes(options().writes_normals()));
}

void PlyWriter::write_formatted_vertices(const unsigned char* records, std::size_t bytes) {
  if (format_ != PlyFormat::ascii)
    throw Error(subject(), "internal error: formatted vertices for binary PLY");
  if (vertex_spool_) {
    vertex_spool_->write(records, bytes);
  } else {
    out_.write(records, bytes);
  }
}

unsigned char* PlyWriter::reserve_positions(std::size_t count) {
  // Binary without normals: a vertex record is its position (ply_vertex_record_bytes).
  if (format_ != PlyFormat::binary_little_endian || options().writes_normals()) return nullptr;
  const std::size_t bytes =
      count * ply_vertex_record_bytes(false) + VertexPlacement::kPositionSlack;
  void* const room = vertex_spool_ ? vertex_spool_->reserve(bytes) : out_.reserve(bytes);
  return static_cast<unsigned char*>(room);
}

void PlyWriter::commit_positions(std::size_t count) {
  const std::size_t bytes = count * ply_vertex_record_bytes(false);
  if (vertex_spool_) {
    vertex_spool_->commit(bytes);
  } else {
    out_.commit(bytes);
  }
}

void PlyWriter::write_faces(const Polygon* faces, std::size_t face_count,
                            std::uint32_t index_offset) {
  if (format_ == PlyFormat::ascii) {
    // "7" and seven indices of at most 10 digits (below 2^32: vertex_limit), each after a
    // space, and the newline; a run of lines at a time, straight into the buffer.
    constexpr std::size_t kMostLineBytes = 1 + kMaxPolygonVertices * 11 + 1;
    put_line_runs(faces_, face_count, kMostLineBytes, [&](char* out, std::size_t i) {
      const Polygon& face = faces[i];
      const int corners = face.vertex_count;
      // MeshWriter checked every face; checked again so that the run provably fits its room.
      if (corners > kMaxPolygonVertices) throw Error(subject(), "internal error: face too large");
      *out++ = static_cast<char>('0' + corners);
      for (int k = 0; k < corners; ++k) {
        *out++ = ' ';
        out = std::to_chars(out, out + 10, face.vertices[k] + index_offset).ptr;
      }
      *out++ = '\n';
      return out;
    });
    return;
  }
  put_ply_faces(faces_, faces, face_count, index_offset, subject());
}

void PlyWriter::complete_file() {
  if (options().part) {
    part_face_bytes_ = faces_.bytes_written();
    faces_.copy_to(out_);
  } else if (vertex_spool_) {
    const std::string header = header_lines(format_, options(), vertices_written(), faces_written(),
                                            index_type(vertices_written())) +
                               kEndHeader;
    out_.write(header.data(), header.size());
    vertex_spool_->copy_to(out_);
    faces_.copy_to(out_);
  } else {
    faces_.copy_to(out_);
    const std::string header =
        padded_header(format_, options(), vertices_written(), faces_written());
    out_.overwrite(0, header.data(), header.size());
  }
  out_.seal();
}

}  // namespace mvox
