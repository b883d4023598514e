#include "write/mesh/mesh_writer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "write/mesh/face_formatter.h"
#include "write/mesh/polygon_scan.h"
#include "write/mesh/polygon_triangulation.h"
#include "write/mesh/stl_triangle_records.h"
#include "write/mesh/vertex_text_formatter.h"

namespace mvox {
namespace {

// Faces handed to the derived writer at a time: 16 KB of Polygon.
constexpr std::size_t kFacesPerRun = 512;
// Polygons whose triangle records are made at a time: at most 32 KB of records, about 12 KB at
// the engine's usual mix, which stay in the first-level cache until their normals are filled in
// (make_stl_triangle_records' second pass).
constexpr std::size_t kTriangleRecordPolygonsPerRun = 128;

MeshWriterOptions checked(MeshWriterOptions options) {
  // The command line checks the placement earlier, naming the input or option it came from
  // (mesh_writer_options in cli_options.h); this guards every other caller.
  options.transform.check("mesh placement");
  for (const std::string& comment : options.comments)
    if (comment.find_first_of("\r\n") != std::string::npos)
      throw Error("mesh comment", "must be one line: \"" + comment + "\"");
  return options;
}

// Adds `offset` to every index of `polygons`, modulo 2^32.
void move_indices(Polygon* polygons, std::size_t count, std::uint32_t offset) {
  for (std::size_t i = 0; i < count; ++i)
    for (int k = 0; k < polygons[i].vertex_count; ++k) polygons[i].vertices[k] += offset;
}

}  // namespace

MeshWriter::MeshWriter(const MeshWriterOptions& options, Faces faces, Positions positions)
    : options_(checked(options)),
      triangulate_(options.triangulate || faces == Faces::as_triangles),
      positions_needed_(positions == Positions::needed),
      needs_geometry_(triangulate_ || positions_needed_),
      mirrors_(options_.transform.mirrors()),
      placement_(options_.transform, options_.writes_normals()),
      corner_placement_(options_.transform),
      faces_(positions_needed_ ? 0 : kFacesPerRun),
      vertex_count_(options_.part ? options_.part->first_vertex : 0) {}

template <class Body>
Status MeshWriter::guarded(const char* batch, Body&& body) {
  // No exception may leave: the engine that calls us is compiled with -fno-exceptions.
  try {
    if (error_) return Status::sink_refused;
    if (finished_)
      throw Error(subject(), std::string("internal error: ") + batch + " after finish()");
    body();
    return Status::ok;
  } catch (const Error& error) {
    if (!error_) error_ = error;
  } catch (const std::exception& error) {
    if (!error_) error_ = Error(subject(), error.what());
  } catch (...) {
    if (!error_) error_ = Error(subject(), "unknown error");
  }
  return Status::sink_refused;
}

Status MeshWriter::consume_vertices(const Vertex* vertices, std::size_t vertex_count) {
  return consume_vertices_with_normals(vertices, nullptr, vertex_count);
}

Status MeshWriter::consume_vertices_with_normals(const Vertex* vertices, const glm::vec3* normals,
                                                 std::size_t vertex_count) {
  return guarded("vertices", [&] {
    if (options_.normals_given && normals == nullptr && vertex_count > 0)
      throw Error(subject(), "internal error: vertices arrived without their normals");
    check_vertex_room(vertex_count);
    if (!write_positions(vertices, vertex_count)) {
      place_vertices(vertices, options_.normals_given ? normals : nullptr, vertex_count);
      write_vertices(vertex_batch_.data(), vertex_count);
    }
    vertex_count_ += vertex_count;
  });
}

bool MeshWriter::write_positions(const Vertex* vertices, std::size_t vertex_count) {
  // Placed once, straight into the buffer the records go out from, rather than into a batch
  // and copied from there: at 1024^3 (8 million vertices) the copy took as long as the placing.
  if (placement_.with_normals() || vertex_count == 0) return false;
  for (std::size_t first = 0; first < vertex_count; first += kPositionsPerRun) {
    const std::size_t run = std::min(kPositionsPerRun, vertex_count - first);
    unsigned char* const records = reserve_positions(run);
    if (!records) {
      if (first == 0) return false;
      throw Error(subject(), "internal error: room for vertex records refused mid-batch");
    }
    if (placement_.place_positions(vertices + first, run, records) != run) {
      // A vertex beyond float's range: the file is refused, in the words of a placed batch.
      place_vertices(vertices, nullptr, vertex_count);
      throw Error(subject(), "internal error: a vertex left float's range only once");
    }
    commit_positions(run);
  }
  return true;
}

void MeshWriter::check_vertex_room(std::size_t vertex_count) const {
  const VertexLimit limit = vertex_limit();
  if (vertex_count > limit.count - std::min(limit.count, vertex_count_))
    throw Error(subject(), limit.problem());
}

void MeshWriter::place_vertices(const Vertex* vertices, const glm::vec3* given,
                                std::size_t vertex_count) {
  // Grown only: a batch smaller than the last keeps the room, so the next larger one is not
  // zero-filled again (place() and compute() write each of the first vertex_count).
  if (vertex_batch_.size() < vertex_count) vertex_batch_.resize(vertex_count);
  const glm::vec3* normals = given;
  if (options_.normals != nullptr) {
    if (normal_batch_.size() < vertex_count) normal_batch_.resize(vertex_count);
    options_.normals->compute(vertices, vertex_count, normal_batch_.data());
    normals = normal_batch_.data();
  }
  const std::size_t outside =
      placement_.place(vertices, normals, vertex_count, vertex_batch_.data());
  if (outside < vertex_count) {
    throw Error(subject(), "vertex " + std::to_string(vertex_count_ + outside) +
                               " lies outside the float range after spacing and origin");
  }
}

Status MeshWriter::consume_placed_vertices(const WorldVertex* vertices, std::size_t vertex_count) {
  return guarded("vertices", [&] {
    check_vertex_room(vertex_count);
    write_vertices(vertices, vertex_count);
    vertex_count_ += vertex_count;
  });
}

std::unique_ptr<FaceFormatter> MeshWriter::face_formatter() const { return nullptr; }

Status MeshWriter::consume_vertex_count(std::size_t vertex_count) {
  return guarded("vertices", [&] {
    if (writes_vertex_records())
      throw Error(subject(), "internal error: vertices counted for a format that writes them");
    check_vertex_room(vertex_count);
    vertex_count_ += vertex_count;
  });
}

Status MeshWriter::consume_formatted_faces(const unsigned char* records, std::size_t bytes,
                                           std::size_t polygon_count, std::size_t face_count) {
  return guarded("formatted faces", [&] {
    if (pending_batch_)
      throw Error(subject(),
                  "internal error: formatted faces arrived before a polygon batch's geometry");
    write_formatted_faces(records, bytes, face_count);
    polygon_count_ += polygon_count;
    face_count_ += face_count;
  });
}

void MeshWriter::write_formatted_faces(const unsigned char*, std::size_t, std::size_t) {
  throw Error(subject(), "internal error: formatted faces for a format that formats its own");
}

std::unique_ptr<VertexTextFormatter> MeshWriter::vertex_text_formatter() const { return nullptr; }

Status MeshWriter::consume_formatted_vertices(const unsigned char* records, std::size_t bytes,
                                              std::size_t vertex_count) {
  return guarded("vertices", [&] {
    check_vertex_room(vertex_count);
    write_formatted_vertices(records, bytes);
    vertex_count_ += vertex_count;
  });
}

void MeshWriter::write_formatted_vertices(const unsigned char*, std::size_t) {
  throw Error(subject(), "internal error: formatted vertices for a format that formats its own");
}

void MeshWriter::restart(std::uint64_t first_vertex) {
  vertex_count_ = first_vertex;
  polygon_count_ = 0;
  face_count_ = 0;
  face_fill_ = 0;
  pending_batch_ = false;
  error_.reset();
}

void MeshWriter::check_polygons(const Polygon* polygons, std::size_t polygon_count,
                                std::uint32_t index_offset) const {
  // The largest index and whether the sizes are in range, folded over the batch without a
  // branch per polygon (polygon_scan.h); the message is built only for a batch that fails. A
  // slab's indices are moved by one offset: below 2^32 vertices every moved index is below 2^32
  // too, so the largest, moved without wrapping, must be in range.
  const PolygonScan scan = scan_polygons(polygons, polygon_count);
  // Below 2^32 vertices an index is its whole self. Beyond, whole_vertex_index() puts every
  // index among the last 2^32 taken: none can be out of range.
  const bool whole = vertex_count_ <= kMaxVerticesBack;
  if (scan.sizes_ok &&
      (polygon_count == 0 || !whole || scan.highest + std::uint64_t{index_offset} < vertex_count_))
    return;
  for (std::size_t i = 0; i < polygon_count; ++i) {
    const Polygon& polygon = polygons[i];
    const int count = polygon.vertex_count;
    const std::string face = "internal error: face " + std::to_string(polygon_count_ + i);
    if (count < 3 || count > kMaxPolygonVertices)
      throw Error(subject(), face + " has " + std::to_string(count) + " vertices");
    for (int k = 0; k < count; ++k) {
      const std::uint64_t moved = polygon.vertices[k] + std::uint64_t{index_offset};
      if (whole && moved >= vertex_count_)
        throw Error(subject(), face + " refers to vertex " + std::to_string(moved) + " of " +
                                   std::to_string(vertex_count_) + " written");
      const std::uint32_t written = static_cast<std::uint32_t>(moved);
      const std::uint64_t index =
          vertex_count_ == 0 ? written : whole_vertex_index(written, vertex_count_);
      if (index >= vertex_count_)
        throw Error(subject(), face + " refers to vertex " + std::to_string(polygon.vertices[k]) +
                                   " of " + std::to_string(vertex_count_) + " written");
    }
  }
}

Status MeshWriter::consume_polygons(const Polygon* polygons, std::size_t polygon_count) {
  return consume_moved_polygons(polygons, polygon_count, 0);
}

Status MeshWriter::consume_moved_polygons(const Polygon* polygons, std::size_t polygon_count,
                                          std::uint32_t index_offset) {
  return guarded("polygons", [&] {
    check_polygons(polygons, polygon_count, index_offset);
    polygon_count_ += polygon_count;
    if (needs_geometry_) {
      if (pending_batch_)
        throw Error(subject(),
                    "internal error: a polygon batch arrived before the previous one's geometry");
      // The batch is valid only during this call: keep it, moved, until its geometry comes.
      pending_.assign(polygons, polygons + polygon_count);
      if (index_offset != 0) move_indices(pending_.data(), polygon_count, index_offset);
      pending_batch_ = true;
      return;
    }
    if (!triangulate_ && !mirrors_) {
      // Nothing to change: the batch goes out as the engine sent it.
      write_faces(polygons, polygon_count, index_offset);
      face_count_ += polygon_count;
      return;
    }
    face_fill_ = 0;
    for (std::size_t i = 0; i < polygon_count; ++i) {
      Polygon moved = polygons[i];
      move_indices(&moved, 1, index_offset);
      add_faces(moved, nullptr);
    }
    flush_faces();
  });
}

Status MeshWriter::consume_polygon_geometry(const PolygonGeometry* polygons,
                                            std::size_t polygon_count) {
  // Geometry for a picture alone: this writer has what it needs from the indices.
  if (!needs_geometry_) return error_ ? Status::sink_refused : Status::ok;
  return guarded("polygon geometry", [&] {
    if (!pending_batch_ || pending_.size() != polygon_count)
      throw Error(subject(), "internal error: polygon geometry does not match the polygon batch");
    for (std::size_t i = 0; i < polygon_count; ++i)
      if (polygons[i].vertex_count != pending_[i].vertex_count)
        throw Error(subject(), "internal error: polygon geometry does not match the polygon batch");
    if (positions_needed_) {
      write_triangle_records(polygons, polygon_count);
    } else {
      face_fill_ = 0;
      for (std::size_t i = 0; i < polygon_count; ++i) add_faces(pending_[i], &polygons[i]);
      flush_faces();
    }
    pending_batch_ = false;
  });
}

void MeshWriter::write_triangle_records(const PolygonGeometry* polygons,
                                        std::size_t polygon_count) {
  for (std::size_t first = 0; first < polygon_count;) {
    const std::size_t run = std::min(kTriangleRecordPolygonsPerRun, polygon_count - first);
    unsigned char* const records =
        reserve_triangle_records(run * kMostStlBytesPerPolygon + kStlRecordSlack);
    const StlRecordsMade made =
        make_stl_triangle_records(corner_placement_, mirrors_, polygons + first, run, records);
    commit_triangle_records(made.triangles * kStlTriangleBytes, made.triangles);
    face_count_ += made.triangles;
    if (made.polygons < run)
      refuse_triangle_records(pending_[first + made.polygons], polygons[first + made.polygons]);
    first += run;
  }
}

void MeshWriter::refuse_triangle_records(const Polygon& polygon,
                                         const PolygonGeometry& geometry) const {
  const int count = polygon.vertex_count;
  if (count < 3 || count > kMaxPolygonVertices || count != geometry.vertex_count)
    throw Error(subject(), "internal error: a polygon of " + std::to_string(count) + " vertices");
  // The problems in the order the faces meet them: the split first, then the corners of each
  // triangle as it is written, so that the corner named is the first one written.
  PolygonTriangles triangles;
  if (!triangulate_polygon(geometry, &triangles))
    throw Error(subject(), "internal error: a " + std::to_string(count) +
                               "-gon cannot be split without a diagonal on a cube face");
  for (int t = 0; t < triangles.count; ++t)
    for (int k = 0; k < 3; ++k) {
      const int corner = triangles.corners[t][mirrors_ ? (3 - k) % 3 : k];
      check_corner(geometry.vertices[corner], polygon.vertices[corner]);
    }
  throw Error(subject(), "internal error: STL records refused a polygon without a reason");
}

void MeshWriter::check_corner(const Vertex& vertex, std::uint32_t index) const {
  const Vector3d world = options_.transform.position(vertex.x, vertex.y, vertex.z);
  for (int axis = 0; axis < 3; ++axis) {
    // Checked when the vertex arrived by index; checked again here because the cast of a
    // double beyond float's range would be undefined behaviour.
    if (!(std::fabs(world[axis]) <= std::numeric_limits<float>::max()))
      throw Error(subject(), "vertex " + std::to_string(index) +
                                 " lies outside the float range after spacing and origin");
  }
}

unsigned char* MeshWriter::reserve_triangle_records(std::size_t) {
  throw Error(subject(), "internal error: triangle records for a format that indexes vertices");
}

void MeshWriter::commit_triangle_records(std::size_t, std::size_t) {
  throw Error(subject(), "internal error: triangle records for a format that indexes vertices");
}

void MeshWriter::add_faces(const Polygon& polygon, const PolygonGeometry* geometry) {
  const std::uint8_t in_order[kMaxPolygonVertices] = {0, 1, 2, 3, 4, 5, 6};
  if (!triangulate_ || polygon.vertex_count == 3) {
    add_face(polygon, in_order, polygon.vertex_count);
    return;
  }
  PolygonTriangles triangles;
  if (!triangulate_polygon(*geometry, &triangles))
    throw Error(subject(), "internal error: a " + std::to_string(polygon.vertex_count) +
                               "-gon cannot be split without a diagonal on a cube face");
  for (int t = 0; t < triangles.count; ++t) add_face(polygon, triangles.corners[t], 3);
}

void MeshWriter::add_face(const Polygon& polygon, const std::uint8_t* corners, int corner_count) {
  // Faces go out in small runs, so the buffer stays small whatever the engine's batch size.
  if (face_fill_ == faces_.size()) flush_faces();
  // Reused without clearing: only the first vertex_count entries of a face are ever read.
  Polygon& face = faces_[face_fill_++];
  face.vertex_count = static_cast<std::uint8_t>(corner_count);
  for (int k = 0; k < corner_count; ++k) {
    // A mirroring transform turns counter-clockwise into clockwise; walking the corners
    // backwards from the first turns it back, so the outward side stays outward.
    const int corner = corners[mirrors_ ? (corner_count - k) % corner_count : k];
    face.vertices[k] = polygon.vertices[corner];
  }
}

void MeshWriter::flush_faces() {
  // add_faces() took polygons already moved.
  write_faces(faces_.data(), face_fill_, 0);
  face_count_ += face_fill_;
  face_fill_ = 0;
}

void MeshWriter::finish() {
  complete();
  publish();
}

void MeshWriter::complete() {
  if (finished_) throw Error(subject(), "internal error: finish() called twice");
  if (error_) throw *error_;
  try {
    if (pending_batch_)
      throw Error(subject(),
                  "internal error: polygons arrived without their geometry (the engine needs "
                  "EngineOptions::polygon_geometry)");
    complete_file();
  } catch (const Error& error) {
    error_ = error;
    throw;
  }
  // A completed file waits only to be published (one per label, mvox extract --labels): its
  // batch buffers go now.
  std::vector<glm::vec3>().swap(normal_batch_);
  std::vector<WorldVertex>().swap(vertex_batch_);
  std::vector<Polygon>().swap(faces_);
  std::vector<Polygon>().swap(pending_);
  finished_ = true;
}

void MeshWriter::publish() {
  if (OutputFile* file = output_file()) file->publish();
}

}  // namespace mvox
