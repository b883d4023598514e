#pragma once
// What every mesh writer (PLY, STL, OBJ) shares: the engine's batches checked, placed in the
// world, split into triangles when asked, wound outward, and errors remembered for finish().
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "error.h"
#include "mvox/polygon_sink.h"
#include "mvox/vertex_normals.h"
#include "write/mesh/corner_placement.h"
#include "write/mesh/vertex_placement.h"
#include "write/mesh/world_transform.h"
#include "write/output_file.h"

namespace mvox {

class FaceFormatter;
class VertexTextFormatter;

struct MeshWriterOptions {
  // Where the mesh lands (world_transform.h). Checked by the writer's constructor.
  WorldTransform transform;
  // One-line descriptions, e.g. "mvox marching voxels, threshold 600, fast engine, merge-rules":
  // PLY comment lines, OBJ "#" lines, and the first one starts the STL header.
  std::vector<std::string> comments;
  // When set (borrowed), every vertex also gets its outward unit normal, turned into the world
  // with the transform: PLY nx, ny, nz, OBJ vn. STL has face normals only and refuses it. The
  // window behind it must hold the slices around each vertex batch as it arrives.
  const VertexNormals* normals = nullptr;
  // Instead of `normals`: every vertex batch comes with its normals, computed by the caller
  // (consume_vertices_with_normals). Slab-parallel extraction does this: each slab has a window
  // of its own, so the normals are computed where the slab is extracted.
  bool normals_given = false;
  bool writes_normals() const { return normals != nullptr || normals_given; }
  // Split every polygon into triangles (polygon_triangulation.h); STL always does.
  bool triangulate = false;
  // Make the file durable before it appears (OutputFile's `sync`, --sync).
  bool sync = false;
  // Set when the file is one part of a mesh that several processes write together (mvox-mpi):
  // it gets no head (no PLY header, no STL header and count, no OBJ comments), only the part's
  // records, and its vertices are numbered on from `first_vertex`, the vertices of the parts
  // before it. The whole file's head is mesh_file_head() (mesh_format.h).
  struct Part {
    std::uint64_t first_vertex = 0;
  };
  std::optional<Part> part;
};

// A PolygonSink that writes a mesh file as the engine streams, in fixed memory whatever the
// mesh size: the derived writer's buffers, a copy of one polygon batch when it waits for its
// geometry (32 bytes a polygon), the placed vertices of one vertex batch (24 bytes a vertex) and
// 512 faces at a time (none for STL, whose records go straight into the file's buffer). Faces go to
// the derived writer as Polygon: indices of vertices already written, wound counter-clockwise seen
// from outside in the world (reversed from the engine's order when the transform mirrors); without
// mirror or triangles they are the engine's batch itself. A format whose faces are STL's triangle
// records (Positions::needed) gets no faces: MeshWriter makes the records from each polygon's
// geometry (stl_triangle_records.h) straight into the room the format gives
// (reserve_triangle_records). The file appears, complete, only when finish() succeeds (OutputFile's
// temporary and rename); on any failure the target is left as it was.
//
// The engine is built without exceptions, so the consume_* calls never throw: on an error they
// remember it and return Status::sink_refused (also for every later call), and finish() throws
// it. Polygons must have 3 to kMaxPolygonVertices vertices, each already consumed; anything
// else is refused as an internal error rather than written into a broken file.
//
// A writer that triangulates or needs face positions (needs_polygon_geometry()) writes each
// polygon batch when its geometry arrives, so the engine must run with
// EngineOptions::polygon_geometry; polygons left without geometry make finish() throw.
class MeshWriter : public PolygonSink {
 public:
  // The most vertices a format can index, and why, for the refusal of one more (e.g. PLY's
  // 32-bit index lists). No limit by default: the indices are whole (whole_vertex_index()).
  struct VertexLimit {
    std::uint64_t count;
    const char* reason;  // "PLY's 32-bit index lists cannot address ..."
    // "more than COUNT vertices, which REASON": the refusal's problem.
    std::string problem() const {
      return "more than " + std::to_string(count) + " vertices, which " + reason;
    }
  };

  virtual ~MeshWriter() = default;
  MeshWriter(const MeshWriter&) = delete;
  MeshWriter& operator=(const MeshWriter&) = delete;

  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) final;
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) final;
  Status consume_polygon_geometry(const PolygonGeometry* polygons, std::size_t polygon_count) final;
  // consume_polygons() for polygons whose indices are each `index_offset` (modulo 2^32) below
  // the ones to write: a slab's polygons, numbered from the slab's first vertex
  // (pipeline/slab_recorder.h). The offset is added as the faces are formatted, so that the
  // caller need not copy the batch to move it.
  Status consume_moved_polygons(const Polygon* polygons, std::size_t polygon_count,
                                std::uint32_t index_offset);
  // consume_vertices() for a writer whose options have normals_given: `normals` holds each
  // vertex's outward unit normal in the volume's axes, as VertexNormals computes it.
  Status consume_vertices_with_normals(const Vertex* vertices, const glm::vec3* normals,
                                       std::size_t vertex_count);
  // consume_vertices() for vertices the caller has placed with placement() already (slab
  // workers do, in parallel), normals included when the options have them.
  Status consume_placed_vertices(const WorldVertex* vertices, std::size_t vertex_count);
  // How this writer places vertices: positions by the options' transform, normals when it
  // writes them.
  const VertexPlacement& placement() const { return placement_; }

  // For a format whose face records hold no vertex indices (STL): a formatter that makes this
  // writer's face records in memory, for a slab worker ahead of its turn (face_formatter.h).
  // Null for the others.
  virtual std::unique_ptr<FaceFormatter> face_formatter() const;
  // For a text format (OBJ, ASCII PLY): a formatter that makes this writer's vertex lines in
  // memory, for a slab worker ahead of its turn (vertex_text_formatter.h). Null for the others.
  virtual std::unique_ptr<VertexTextFormatter> vertex_text_formatter() const;
  // For a writer that has a vertex_text_formatter(): the lines its formatter made for
  // `vertex_count` placed vertices, `bytes` long, appended as they are.
  Status consume_formatted_vertices(const unsigned char* records, std::size_t bytes,
                                    std::size_t vertex_count);
  // False for a format that writes no vertex records (STL: its triangles hold their positions).
  virtual bool writes_vertex_records() const { return true; }
  // For a writer that writes no vertex records: `vertex_count`
  // vertices that the caller placed, all within float's range, counted and not written.
  Status consume_vertex_count(std::size_t vertex_count);
  // For a writer that has a face_formatter(): the records its formatter made for
  // `polygon_count` polygons, `face_count` faces, `bytes` long, appended as they are.
  Status consume_formatted_faces(const unsigned char* records, std::size_t bytes,
                                 std::size_t polygon_count, std::size_t face_count);

  // Completes and commits the file. Throws the remembered error of a refused batch, or any
  // error of its own; throws if called twice.
  void finish();
  // finish() in two steps, to make the mesh appear together with other files (OutputFile's
  // seal() and publish()): complete() writes and seals everything, publish() only renames.
  void complete();
  void publish();

  bool needs_polygon_geometry() const { return needs_geometry_; }
  // Vertices received from the engine (STL repeats them in every triangle instead), after a
  // part's first_vertex.
  std::uint64_t vertices_written() const { return vertex_count_; }
  // Faces written: triangles when triangulating.
  std::uint64_t faces_written() const { return face_count_; }
  // For a part (MeshWriterOptions::part), once complete: how many of its bytes, at the end, go
  // among the whole file's faces (PLY's face records); the bytes before them go among its
  // vertices. Formats of one section (STL, OBJ) have none.
  virtual std::uint64_t part_face_bytes() const { return 0; }
  // The error that made the writer refuse, or nullptr.
  const Error* error() const { return error_ ? &*error_ : nullptr; }
  // The output's name in messages: the path, or "standard output".
  virtual const std::string& subject() const = 0;
  // The file being written, for publishing it together with other outputs (publish_together);
  // null for a writer that keeps the mesh in memory (mesh_arrays.h).
  virtual OutputFile* output_file() = 0;

  // The most vertices placed straight into a writer's buffer at a time (reserve_positions).
  static constexpr std::size_t kPositionsPerRun = 8192;

 protected:
  enum class Faces : std::uint8_t { as_polygons, as_triangles };
  // `needed`: the format's faces are triangles that carry their corners' positions instead of
  // vertex indices (STL), made by MeshWriter as records into reserve_triangle_records()' room.
  enum class Positions : std::uint8_t { not_needed, needed };

  // Checks the options (throws mvox::Error) before the derived writer creates any file.
  MeshWriter(const MeshWriterOptions& options, Faces faces, Positions positions);

  const MeshWriterOptions& options() const { return options_; }

  virtual VertexLimit vertex_limit() const { return {~std::uint64_t{0}, "64 bits cannot count"}; }

  // The derived writer's format. May throw mvox::Error; the base turns that into a refusal.
  // Faces carry indices modulo 2^32 (mvox/mesh.h): whole_vertex_index(index, vertices_written())
  // is the whole one, the same number while fewer than 2^32 vertices have been written.
  virtual void write_vertices(const WorldVertex* vertices, std::size_t vertex_count) = 0;
  // For a format whose vertex records are the positions alone, as VertexPlacement::
  // place_positions() makes them (binary PLY without normals): room in the file's buffer for
  // `count` records and VertexPlacement::kPositionSlack bytes more, count at most
  // kPositionsPerRun. The vertices are then placed straight into it, and commit_positions()
  // appends them, instead of a placed batch going to write_vertices(). Null (the default): the
  // format takes placed vertices.
  virtual unsigned char* reserve_positions(std::size_t /*count*/) { return nullptr; }
  virtual void commit_positions(std::size_t /*count*/) {}
  // Each index plus `index_offset`, modulo 2^32, is the index to write. Not called for a format
  // of triangle records (Positions::needed).
  virtual void write_faces(const Polygon* faces, std::size_t face_count,
                           std::uint32_t index_offset) = 0;
  // For a format of triangle records (Positions::needed): room for `bytes` of them (at most
  // BufferedWriter::kBufferBytes) where the format's records go, filled by
  // make_stl_triangle_records(); then the first `bytes` of it, `triangle_count` records, are
  // appended. Throws (an internal error) for the other formats.
  virtual unsigned char* reserve_triangle_records(std::size_t bytes);
  virtual void commit_triangle_records(std::size_t bytes, std::size_t triangle_count);
  // Writes what only the end can tell (counts), and seals the file (OutputFile::seal).
  virtual void complete_file() = 0;
  // The records of consume_formatted_faces(); only writers with a face_formatter() get them.
  virtual void write_formatted_faces(const unsigned char* records, std::size_t bytes,
                                     std::size_t face_count);
  // The lines of consume_formatted_vertices(); only writers with a vertex_text_formatter() get
  // them.
  virtual void write_formatted_vertices(const unsigned char* records, std::size_t bytes);
  // Starts over, counting vertices from `first_vertex`, as a writer of a part that starts there
  // (a FaceFormatter's next slab). Forgets the counts, a waiting polygon batch and an error. A
  // writer once completed stays so, and refuses every batch (its buffers are gone).
  void restart(std::uint64_t first_vertex);

 private:
  template <class Body>
  Status guarded(const char* batch, Body&& body);
  // Throws unless `vertex_count` more vertices stay within the format's vertex_limit().
  void check_vertex_room(std::size_t vertex_count) const;
  // `given`: the batch's normals when the caller computed them (normals_given), else null.
  void place_vertices(const Vertex* vertices, const glm::vec3* given, std::size_t vertex_count);
  // Places the batch straight into the file's buffer (reserve_positions); false when the format
  // takes placed vertices. Throws, naming the vertex as place_vertices() does, when one leaves
  // float's range.
  bool write_positions(const Vertex* vertices, std::size_t vertex_count);
  // Throws unless every polygon has 3 to kMaxPolygonVertices vertices, each already consumed
  // (once moved by `index_offset`).
  void check_polygons(const Polygon* polygons, std::size_t polygon_count,
                      std::uint32_t index_offset) const;
  // Appends `polygon`'s faces (itself, or its triangles when `geometry` is given and the writer
  // triangulates) to faces_.
  void add_faces(const Polygon& polygon, const PolygonGeometry* geometry);
  void add_face(const Polygon& polygon, const std::uint8_t* corners, int corner_count);
  void flush_faces();
  // The triangle records of `polygon_count` polygons (pending_) from their geometry, into the
  // format's room (reserve_triangle_records), a run at a time.
  void write_triangle_records(const PolygonGeometry* polygons, std::size_t polygon_count);
  // Throws the problem that kept make_stl_triangle_records() from making `polygon`'s records:
  // no fan that avoids the cube faces, or else the first corner beyond float's range in the
  // order the triangles write them, named by its index.
  [[noreturn]] void refuse_triangle_records(const Polygon& polygon,
                                            const PolygonGeometry& geometry) const;
  // The careful placement of a corner: throws, naming `index`, when a coordinate leaves
  // float's range.
  void check_corner(const Vertex& vertex, std::uint32_t index) const;

  MeshWriterOptions options_;
  bool triangulate_;
  bool positions_needed_;
  bool needs_geometry_;
  bool mirrors_;
  VertexPlacement placement_;
  CornerPlacement corner_placement_;  // with positions (STL): a polygon's corners at a time
  std::vector<glm::vec3> normal_batch_;
  std::vector<WorldVertex> vertex_batch_;
  // kFacesPerRun faces, the first face_fill_ in use (none for triangle records).
  std::vector<Polygon> faces_;
  std::size_t face_fill_ = 0;
  std::vector<Polygon> pending_;  // a polygon batch waiting for its geometry, moved
  bool pending_batch_ = false;
  std::uint64_t vertex_count_ = 0;
  std::uint64_t polygon_count_ = 0;
  std::uint64_t face_count_ = 0;
  std::optional<Error> error_;
  bool finished_ = false;
};

}  // namespace mvox
