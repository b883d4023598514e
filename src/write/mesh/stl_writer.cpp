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

}  // namespace

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

void StlWriter::write_faces(const Polygon* faces, const FacePositions* positions,
                            std::size_t face_count, std::uint32_t /*index_offset: no indices*/) {
  if (!positions) throw Error(subject(), "internal error: STL faces without positions");
  if (face_count > std::numeric_limits<std::uint32_t>::max() - faces_written())
    throw Error(subject(), "more than 4,294,967,295 triangles, which STL cannot count");
  if (spool_) {
    put_stl_triangles(*spool_, faces, positions, face_count, subject());
  } else {
    put_stl_triangles(out_, faces, positions, face_count, subject());
  }
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
