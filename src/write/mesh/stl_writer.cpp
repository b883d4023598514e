#include "write/mesh/stl_writer.h"

#include <strings.h>  // strncasecmp

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "write/mesh/little_endian.h"

namespace mvox {
namespace {

const MeshWriterOptions& without_vertex_normals(const MeshWriterOptions& options) {
  if (options.writes_normals())
    throw Error("--normals", "STL has face normals only; write PLY or OBJ for vertex normals");
  return options;
}

// The unit normal of the triangle as written (float vertices, computed in double), by the
// right-hand rule; zero when the rounded vertices have no area.
void face_normal(const float (*p)[3], float normal[3]) {
  double u[3], v[3];
  for (int i = 0; i < 3; ++i) {
    u[i] = double{p[1][i]} - p[0][i];
    v[i] = double{p[2][i]} - p[0][i];
  }
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int i = 0; i < 3; ++i) normal[i] = length > 0.0 ? static_cast<float>(n[i] / length) : 0.0f;
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
    write_triangles_to(*spool_, faces, positions, face_count);
  } else {
    write_triangles_to(out_, faces, positions, face_count);
  }
}

template <class Sink>
void StlWriter::write_triangles_to(Sink& sink, const Polygon* faces, const FacePositions* positions,
                                   std::size_t face_count) {
  // Records are formatted straight into the file's buffer, a run at a time.
  constexpr std::size_t kPerRun = BufferedWriter::kBufferBytes / kTriangleBytes;
  for (std::size_t first = 0; first < face_count; first += kPerRun) {
    const std::size_t count = std::min(kPerRun, face_count - first);
    auto* end = reinterpret_cast<unsigned char*>(sink.reserve(count * kTriangleBytes));
    for (std::size_t i = first; i < first + count; ++i) {
      if (faces[i].vertex_count != 3)
        throw Error(subject(), "internal error: an STL face with " +
                                   std::to_string(faces[i].vertex_count) + " vertices");
      const float(*p)[3] = positions[i].xyz;
      float normal[3];
      face_normal(p, normal);
      for (float value : normal) end = store_le_float(end, value);
      for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis) end = store_le_float(end, p[k][axis]);
      *end++ = 0;  // attribute byte count: 0, as nearly every reader expects
      *end++ = 0;
    }
    sink.commit(count * kTriangleBytes);
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
