#include "ply_writer.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace mvox {
namespace {

// PLY "int" indices are signed 32-bit: vertex 2^31 - 1 is the last one a face can name.
// Counts are reserved at their widest: 20 digits, enough for any 64-bit value.
constexpr std::uint64_t kWidestCount = std::numeric_limits<std::uint64_t>::max();
constexpr char kEndHeader[] = "end_header\n";
constexpr std::size_t kEndHeaderBytes = sizeof kEndHeader - 1;
// The padding line is "comment" followed by at least one space, so it is never empty.
constexpr std::size_t kShortestPaddingBytes = sizeof "comment \n" - 1;

PlyWriterOptions checked(PlyWriterOptions options) {
  static const char* const kAxis[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    const double spacing = options.spacing[axis];
    if (!(spacing > 0.0 && spacing <= std::numeric_limits<float>::max())) {
      throw Error(std::string("spacing ") + kAxis[axis],
                  "must be positive and finite, got " + std::to_string(spacing));
    }
    if (!(std::fabs(options.origin[axis]) <= std::numeric_limits<float>::max())) {
      throw Error(std::string("origin ") + kAxis[axis],
                  "must be finite, got " + std::to_string(options.origin[axis]));
    }
  }
  for (const std::string& comment : options.comments) {
    if (comment.find_first_of("\r\n") != std::string::npos) {
      throw Error("PLY comment", "must be one line: \"" + comment + "\"");
    }
  }
  return options;
}

// The header without its padding line and end_header.
std::string header_lines(const PlyWriterOptions& options, std::uint64_t vertex_count,
                         std::uint64_t face_count) {
  std::string text = "ply\n";
  text += options.format == PlyFormat::ascii ? "format ascii 1.0\n"
                                             : "format binary_little_endian 1.0\n";
  for (const std::string& comment : options.comments) text += "comment " + comment + "\n";
  text += "element vertex " + std::to_string(vertex_count) + "\n";
  text += "property float x\nproperty float y\nproperty float z\n";
  if (options.normals) text += "property float nx\nproperty float ny\nproperty float nz\n";
  text += "element face " + std::to_string(face_count) + "\n";
  text += "property list uchar int vertex_indices\n";
  return text;
}

// Little-endian by shifts, so the file is the same on any host.
inline unsigned char* store_le32(unsigned char* out, std::uint32_t value) {
  out[0] = static_cast<unsigned char>(value);
  out[1] = static_cast<unsigned char>(value >> 8);
  out[2] = static_cast<unsigned char>(value >> 16);
  out[3] = static_cast<unsigned char>(value >> 24);
  return out + 4;
}

inline std::uint32_t float_bits(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

}  // namespace

std::size_t PlyWriter::reserved_header_bytes(const PlyWriterOptions& options) {
  return header_lines(options, kWidestCount, kWidestCount).size() + kShortestPaddingBytes +
         kEndHeaderBytes;
}

PlyWriter::PlyWriter(const std::string& path, PlyWriterOptions options)
    : options_(checked(std::move(options))),
      out_(path),
      faces_(out_.scratch_directory(), out_.subject()) {
  if (out_.can_overwrite()) {
    // Placeholder until finish(): the same size as the real header, so nothing moves.
    header_bytes_ = reserved_header_bytes(options_);
    const std::string placeholder(header_bytes_, ' ');
    out_.write(placeholder.data(), placeholder.size());
  } else {
    vertex_spool_.emplace(out_.scratch_directory(), out_.subject());
  }
}

Status PlyWriter::refuse(const Error& error) {
  if (!error_) error_ = error;
  return Status::sink_refused;
}

template <class Body>
Status PlyWriter::guarded(const char* batch, Body&& body) {
  // No exception may leave: the engine that calls us is compiled with -fno-exceptions.
  try {
    if (error_) return Status::sink_refused;
    if (finished_)
      throw Error(out_.subject(), std::string("internal error: ") + batch + " after finish()");
    body();
    return Status::ok;
  } catch (const Error& error) {
    return refuse(error);
  } catch (const std::exception& error) {
    return refuse(Error(out_.subject(), error.what()));
  } catch (...) {
    return refuse(Error(out_.subject(), "unknown error"));
  }
}

Status PlyWriter::consume_vertices(const Vertex* vertices, std::size_t vertex_count) {
  return guarded("vertices", [&] {
    if (vertex_count > kMaxVertexCount - vertex_count_) {
      throw Error(out_.subject(), "more than " + std::to_string(kMaxVertexCount) +
                                      " vertices, which PLY int indices cannot address");
    }
    if (vertex_spool_) {
      write_vertices(*vertex_spool_, vertices, vertex_count);
    } else {
      write_vertices(out_, vertices, vertex_count);
    }
  });
}

template <class Sink>
void PlyWriter::write_vertices(Sink& sink, const Vertex* vertices, std::size_t vertex_count) {
  const std::array<double, 3>& spacing = options_.spacing;
  const std::array<double, 3>& origin = options_.origin;
  const bool ascii = options_.format == PlyFormat::ascii;
  const bool with_normals = options_.normals != nullptr;
  if (with_normals) {
    normal_batch_.resize(vertex_count);
    options_.normals->compute(vertices, vertex_count, normal_batch_.data());
  }
  for (std::size_t i = 0; i < vertex_count; ++i) {
    const Vertex& vertex = vertices[i];
    const double position[3] = {origin[0] + spacing[0] * vertex.x,
                                origin[1] + spacing[1] * vertex.y,
                                origin[2] + spacing[2] * vertex.z};
    float written[6];
    const int fields = with_normals ? 6 : 3;
    if (with_normals)
      for (int axis = 0; axis < 3; ++axis) written[3 + axis] = normal_batch_[i][axis];
    for (int axis = 0; axis < 3; ++axis) {
      // Converting a double beyond float's range is undefined behaviour, so check first.
      if (!(std::fabs(position[axis]) <= std::numeric_limits<float>::max())) {
        throw Error(out_.subject(), "vertex " + std::to_string(vertex_count_) +
                                        " lies outside the float range after spacing and origin");
      }
      written[axis] = static_cast<float>(position[axis]);
    }
    if (ascii) {
      // Shortest representation that reads back to the same float.
      char line[128];
      char* end = line;
      for (int field = 0; field < fields; ++field) {
        end = std::to_chars(end, line + sizeof line, written[field]).ptr;
        *end++ = field + 1 < fields ? ' ' : '\n';
      }
      sink.write(line, static_cast<std::size_t>(end - line));
    } else {
      unsigned char record[24];
      unsigned char* end = record;
      for (int field = 0; field < fields; ++field)
        end = store_le32(end, float_bits(written[field]));
      sink.write(record, static_cast<std::size_t>(end - record));
    }
    ++vertex_count_;
  }
}

Status PlyWriter::consume_polygons(const Polygon* polygons, std::size_t polygon_count) {
  return guarded("polygons", [&] { write_polygons(polygons, polygon_count); });
}

void PlyWriter::write_polygons(const Polygon* polygons, std::size_t polygon_count) {
  const bool ascii = options_.format == PlyFormat::ascii;
  for (std::size_t i = 0; i < polygon_count; ++i) {
    const Polygon& polygon = polygons[i];
    const int count = polygon.vertex_count;
    if (count < 3 || count > kMaxPolygonVertices) {
      throw Error(out_.subject(), "internal error: face " + std::to_string(face_count_) + " has " +
                                      std::to_string(count) + " vertices");
    }
    for (int k = 0; k < count; ++k) {
      if (polygon.vertices[k] >= vertex_count_) {
        throw Error(out_.subject(), "internal error: face " + std::to_string(face_count_) +
                                        " refers to vertex " + std::to_string(polygon.vertices[k]) +
                                        " of " + std::to_string(vertex_count_) + " written");
      }
    }
    if (ascii) {
      // "7" and seven indices of at most 10 digits, each after a space, and the newline.
      char line[1 + kMaxPolygonVertices * 11 + 1];
      char* end = line;
      *end++ = static_cast<char>('0' + count);
      for (int k = 0; k < count; ++k) {
        *end++ = ' ';
        end = std::to_chars(end, line + sizeof line, polygon.vertices[k]).ptr;
      }
      *end++ = '\n';
      faces_.write(line, static_cast<std::size_t>(end - line));
    } else {
      unsigned char record[1 + 4 * kMaxPolygonVertices];
      unsigned char* end = record;
      *end++ = static_cast<unsigned char>(count);
      for (int k = 0; k < count; ++k) end = store_le32(end, polygon.vertices[k]);
      faces_.write(record, static_cast<std::size_t>(end - record));
    }
    ++face_count_;
  }
}

void PlyWriter::finish() {
  complete();
  publish();
}

void PlyWriter::complete() {
  if (finished_) throw Error(out_.subject(), "internal error: finish() called twice");
  if (error_) throw *error_;
  try {
    std::string header = header_lines(options_, vertex_count_, face_count_);
    if (vertex_spool_) {
      header += kEndHeader;
      out_.write(header.data(), header.size());
      vertex_spool_->copy_to(out_);
      faces_.copy_to(out_);
    } else {
      faces_.copy_to(out_);
      // Pad with spaces in a comment line so the header fills its reserved area exactly.
      header += "comment";
      header.append(header_bytes_ - header.size() - kEndHeaderBytes - 1, ' ');
      header += '\n';
      header += kEndHeader;
      out_.overwrite(0, header.data(), header.size());
    }
    out_.seal();
  } catch (const Error& error) {
    error_ = error;
    throw;
  }
  finished_ = true;
}

void PlyWriter::publish() { out_.publish(); }

}  // namespace mvox
