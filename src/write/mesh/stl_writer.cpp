#include "write/mesh/stl_writer.h"

#include <strings.h>  // strncasecmp

#include <algorithm>
#include <cstring>
#include <limits>

#include "write/mesh/binary_records.h"
#include "write/mesh/little_endian.h"

namespace mvox {
namespace {

const MeshWriterOptions& without_vertex_normals(const MeshWriterOptions& options) {
  if (options.writes_normals())
    throw Error("--normals", "STL has face normals only; write PLY or OBJ for vertex normals");
  return options;
}

// StlWriter's triangles, formatted into memory by a slab worker (face_formatter.h).
class StlFaceFormatter final : public FaceFormatter {
 public:
  explicit StlFaceFormatter(const MeshWriterOptions& options)
      : FaceFormatter(options, Faces::as_triangles, Positions::needed, "STL faces") {}
  bool writes_vertex_records() const override { return false; }
  std::size_t most_bytes_per_polygon() const override { return StlWriter::kMostBytesPerPolygon; }

 private:
  void write_vertices(const WorldVertex*, std::size_t) override {}
  void write_faces(const Polygon*, std::size_t, std::uint32_t) override {
    throw Error(subject(), "internal error: STL faces without their geometry");
  }
  unsigned char* reserve_triangle_records(std::size_t bytes) override {
    return static_cast<unsigned char*>(records().reserve(bytes));
  }
  void commit_triangle_records(std::size_t bytes, std::size_t) override { records().commit(bytes); }
};

}  // namespace

std::unique_ptr<FaceFormatter> StlWriter::face_formatter() const {
  MeshWriterOptions options = this->options();
  options.part = MeshWriterOptions::Part{};  // no head; FaceFormatter::start_slab numbers it
  options.sync = false;
  return std::make_unique<StlFaceFormatter>(options);
}

std::string StlWriter::head(const MeshWriterOptions& options, std::uint64_t triangle_count) {
  if (triangle_count > std::numeric_limits<std::uint32_t>::max())
    throw Error("STL", "more than 4,294,967,295 triangles, which STL cannot count");
  std::string text = header(options);
  unsigned char count[4];
  store_le32(count, static_cast<std::uint32_t>(triangle_count));
  text.append(reinterpret_cast<const char*>(count), sizeof count);
  return text;
}

std::string StlWriter::header(const MeshWriterOptions& options) {
  std::string text = options.comments.empty() ? "mvox" : options.comments.front();
  // A binary STL whose header starts with "solid" is taken for ASCII STL by many readers.
  if (text.size() >= 5 && strncasecmp(text.c_str(), "solid", 5) == 0) text = "mvox: " + text;
  text.resize(kHeaderBytes, ' ');
  return text;
}

StlWriter::StlWriter(const std::string& path, const MeshWriterOptions& options)
    : MeshWriter(without_vertex_normals(options), Faces::as_triangles, Positions::needed),
      out_(path, options.sync) {
  if (options.part) {
    // A part has no header: only its triangles.
  } else if (out_.can_overwrite()) {
    // The count is a placeholder until complete_file().
    std::string start = header(options);
    start.append(4, '\0');
    out_.write(start.data(), start.size());
  } else {
    spool_.emplace(out_.scratch_directory(), out_.subject());
  }
}

void StlWriter::write_vertices(const WorldVertex*, std::size_t) {
  // Vertices are written with each triangle, from the polygon geometry.
}

void StlWriter::write_faces(const Polygon*, std::size_t, std::uint32_t) {
  throw Error(subject(), "internal error: STL faces without their geometry");
}

unsigned char* StlWriter::reserve_triangle_records(std::size_t bytes) {
  return reinterpret_cast<unsigned char*>(spool_ ? spool_->reserve(bytes) : out_.reserve(bytes));
}

void StlWriter::commit_triangle_records(std::size_t bytes, std::size_t triangle_count) {
  check_triangle_room(triangle_count);
  if (spool_) {
    spool_->commit(bytes);
  } else {
    out_.commit(bytes);
  }
}

void StlWriter::write_formatted_faces(const unsigned char* records, std::size_t bytes,
                                      std::size_t face_count) {
  if (bytes != face_count * kStlTriangleBytes)
    throw Error(subject(), "internal error: formatted STL records of the wrong size");
  check_triangle_room(face_count);
  if (spool_) {
    spool_->write(records, bytes);
  } else {
    out_.write(records, bytes);
  }
}

static_assert(StlWriter::kMostBytesPerPolygon == (kMaxPolygonVertices - 2) * kStlTriangleBytes);

void StlWriter::check_triangle_room(std::size_t face_count) const {
  if (face_count > std::numeric_limits<std::uint32_t>::max() - faces_written())
    throw Error(subject(), "more than 4,294,967,295 triangles, which STL cannot count");
}

void StlWriter::complete_file() {
  if (options().part) {
    // The head, with the whole mesh's count, is mesh_file_head()'s.
  } else if (spool_) {
    const std::string start = head(options(), faces_written());
    out_.write(start.data(), start.size());
    spool_->copy_to(out_);
  } else {
    unsigned char count[4];
    store_le32(count, static_cast<std::uint32_t>(faces_written()));
    out_.overwrite(kHeaderBytes, count, sizeof count);
  }
  out_.seal();
}

}  // namespace mvox
