#pragma once
// What a slab's engine emits, kept in order so that it can be replayed later into the real sinks
// with the vertex indices moved (Engine::begin_slab): the slab-parallel pipeline's unit of
// hand-over between a worker and the thread that writes (slab_extraction.h).
//
// A chunk keeps the engine's calls exactly as they came, batch by batch, so that a sink fed by
// the replay sees the same sequence of calls, of the same sizes, as one engine over the whole
// volume would make: any sink (OBJ interleaves "v" and "f" lines as batches come) then writes
// the same bytes.
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "mvox/engine.h"
#include "mvox/polygon_sink.h"
#include "mvox/vertex_normals.h"
#include "write/mesh/face_formatter.h"
#include "write/mesh/uninitialized_array.h"
#include "write/mesh/vertex_placement.h"
#include "write/mesh/vertex_text_formatter.h"

namespace mvox {

class MeshWriter;

// How a slab ended, carried by its last chunk.
struct SlabSummary {
  EngineCounters counters;
  // Local index of the first vertex the slab's last slice emitted: the next slab's shared
  // vertices start there (Engine::begin_slab).
  std::uint64_t last_slice_first_vertex = 0;
};

struct SlabChunk {
  // placed_vertices: a vertex batch the worker placed (VertexPlacement); vertices: one left
  // for the writer to place, because a vertex leaves float's range there (the writer then
  // refuses it, naming the vertex as one thread would).
  // vertex_count: a vertex batch of a format that writes no vertex records (STL), placed
  // within float's range, of which only the count is kept. formatted_faces: a polygon batch
  // and its geometry, formatted by the slab's FaceFormatter (face_formatter.h).
  // formatted_vertices: a vertex batch placed within float's range, and its lines formatted by
  // the slab's VertexTextFormatter (vertex_text_formatter.h).
  enum class Kind : std::uint8_t {
    placed_vertices,
    vertices,
    polygons,
    geometry,
    vertex_count,
    formatted_faces,
    formatted_vertices
  };
  struct Call {
    Kind kind;
    // Polygons emitted after the slab's first layer: none refers to a shared vertex, so that
    // moving their indices is one addition.
    bool own_vertices_only;
    std::uint32_t count;
  };
  std::vector<Call> calls;
  // Placed vertices: the first placed_count. Growing leaves them unwritten (place() writes
  // each), and it keeps its size when cleared.
  UninitializedArray<WorldVertex> placed;
  std::size_t placed_count = 0;
  std::vector<Vertex> vertices;    // batches left unplaced (reserved only when needed)
  std::vector<glm::vec3> normals;  // theirs, when the slab computes normals
  std::vector<Polygon> polygons;
  std::vector<PolygonGeometry> geometry;
  // The records of the formatted_faces and formatted_vertices calls, one after the other, and
  // each call's face (or vertex) count and record bytes.
  FormattedRecords formatted;
  struct FormattedRun {
    std::uint32_t count;  // faces, or a formatted_vertices call's vertices
    std::uint32_t bytes;
  };
  std::vector<FormattedRun> formatted_runs;
  bool first = false;                 // the slab's first chunk: `shared_vertices` is valid
  std::uint64_t shared_vertices = 0;  // EngineCounters::shared_vertices after begin_slab
  bool last = false;                  // the slab's last chunk: `summary` is valid
  SlabSummary summary;

  std::size_t bytes() const {
    return placed_count * sizeof(WorldVertex) + vertices.size() * sizeof(Vertex) +
           normals.size() * sizeof(glm::vec3) + polygons.size() * sizeof(Polygon) +
           geometry.size() * sizeof(PolygonGeometry) + formatted.size() +
           calls.size() * sizeof(Call);
  }
  // Empties it for reuse; the vectors keep their capacity, so memory stays what it was.
  void clear();
  // Gives each array room for everything a chunk can hold (SlabRecorder::kChunkBytes and one
  // more batch of the engine's), so that filling it never reallocates: the memory a chunk takes
  // is then the pages it has touched, and no freed copy is left behind in the allocator.
  // `formatted_bytes_per_polygon`: FaceFormatter::most_bytes_per_polygon() when the slabs'
  // faces are formatted by their workers, else 0. Then the engine's batches are not reserved:
  // a chunk keeps them only for a slab whose formatter refused one, in a run the writer then
  // refuses too. `formatted_bytes_per_vertex`: VertexTextFormatter::most_bytes_per_vertex()
  // when the slabs' vertex lines are formatted by their workers, else 0; then vertex batches
  // are kept as text instead of placed (the two formatters never come together: a format
  // whose faces hold no index writes no vertex records).
  void reserve(const EngineOptions& engine, std::size_t formatted_bytes_per_polygon = 0,
               std::size_t formatted_bytes_per_vertex = 0);
  // The bytes reserve() gives: the most a chunk's arrays take once a run has touched them all
  // (one chunk may fill its vertices, the next its polygons).
  static std::size_t reserved_bytes(const EngineOptions& engine,
                                    std::size_t formatted_bytes_per_polygon = 0,
                                    std::size_t formatted_bytes_per_vertex = 0);
};

class SlabReplay;

// The sink a slab's engine writes into: appends each call to the current chunk and, when the
// chunk holds kChunkBytes or more, hands it on with `full(chunk)` and takes an empty one with
// `take()`. Vertex batches are placed as the writer would place them (`placement`, the
// writer's), here, in parallel; with `normals`, each batch's normals are computed as it
// arrives, while the slab's window holds the slices around it.
//
// Once every slab before this one is written, the handover may give a writer (`writer()`): the
// recorder then writes each call straight into it, moving indices as a replay would, instead of
// recording it. The thread extracting the lowest unwritten slab thus writes as it goes, and
// only the slabs ahead of it are recorded.
class SlabRecorder final : public PolygonSink {
 public:
  static constexpr std::size_t kChunkBytes = std::size_t{512} << 10;

  struct Handover {
    virtual SlabChunk* take() = 0;            // an empty chunk; null when the run is cancelled
    virtual void full(SlabChunk* chunk) = 0;  // a chunk for the writer, in order
    // Asked before each call is recorded. Null: record it. Otherwise every slab before this one
    // is written, and so is what this one recorded, `current` included (now emptied): the
    // call goes to the returned replay, which the recorder may use until the slab ends.
    virtual SlabReplay* writer(SlabChunk* /*current*/) { return nullptr; }
    // A call written straight into the writer was refused with `status`.
    virtual void refused(Status /*status*/) {}
    // Between two slices: a chance to write what was recorded if the turn has come, since the
    // engine may go a while without a call.
    virtual void poll() {}

   protected:
    ~Handover() = default;
  };

  // `geometry_follows`: the engine sends a geometry batch after each polygon batch
  // (EngineOptions::polygon_geometry), and the pair is kept in one chunk. With `placement`
  // null, nothing the engine emits is kept, only how each slab starts and ends (a run that
  // draws a picture and writes no mesh).
  // `formatter` (borrowed; may be null): the writer's FaceFormatter (MeshWriter::face_formatter),
  // for a format whose face records hold no indices. The slab's faces are then recorded
  // formatted, and its vertex batches as counts only. Should the formatter refuse a batch, the
  // rest of the slab is recorded as the engine made it, so that the writer refuses it as with
  // one thread, in the same words.
  // `vertex_text` (borrowed; may be null): the writer's VertexTextFormatter
  // (MeshWriter::vertex_text_formatter), for a text format. Vertex batches are then recorded as
  // their lines; a batch with a vertex outside float's range is recorded as the engine made it.
  SlabRecorder(Handover& handover, const VertexPlacement* placement, const VertexNormals* normals,
               bool geometry_follows, FaceFormatter* formatter = nullptr,
               VertexTextFormatter* vertex_text = nullptr);

  // Starts recording a slab, whose engine numbered `shared_vertices` vertices it does not emit,
  // into a fresh chunk. False when the run is cancelled.
  bool start(std::uint64_t shared_vertices);
  // From here on, the slab's polygons refer only to its own vertices: call after the engine
  // has taken the slab's first slice (the layer that joins it to the slice before). Exact
  // because the engine hands on all of a layer's polygons before push_slice() returns
  // (Engine::emit_layer flushes its batches).
  void own_vertices_only() { own_only_ = true; }
  // Ends the slab: its last chunk carries `summary`.
  void end(const SlabSummary& summary);
  // Between two slices of the slab (Handover::poll).
  void poll() { handover_.poll(); }

  Status consume_vertices(const Vertex* vertices, std::size_t count) override;
  Status consume_polygons(const Polygon* polygons, std::size_t count) override;
  Status consume_polygon_geometry(const PolygonGeometry* polygons, std::size_t count) override;

  // Seconds inside the writer for calls written straight into it.
  double write_seconds() const { return write_seconds_; }

 private:
  // The status of a call written straight into the writer, timed; a refusal is reported.
  Status written(Status status, double seconds);
  // Hands the chunk on once it is full; false when the run is cancelled.
  bool after_call();
  // Formats the polygon batch just recorded, with its `geometry`, into the chunk in its place.
  // False, with nothing of it kept and formatting stopped for the slab, if the formatter
  // refuses it.
  bool format_recorded_batch(const PolygonGeometry* geometry, std::size_t count);
  // Places the batch into placed_batch_; false when a vertex leaves float's range.
  bool place_batch(const Vertex* vertices, const glm::vec3* normals, std::size_t count);
  // Appends the call and its batch to the current chunk.
  template <class Item>
  void record(SlabChunk::Kind kind, std::vector<Item>& items, const Item* batch, std::size_t count);

  Handover& handover_;
  const VertexPlacement* placement_;
  const VertexNormals* normals_;
  // One vertex batch's normals before they are placed: at most EngineOptions::vertices_per_batch.
  // Like placed_batch_, only ever grown, so that a batch is not zeroed before it is filled.
  std::vector<glm::vec3> batch_normals_;
  bool geometry_follows_;
  FaceFormatter* formatter_;
  VertexTextFormatter* vertex_text_;
  bool formatting_ = false;  // the current slab's faces are recorded formatted
  bool own_only_ = false;
  SlabChunk* chunk_ = nullptr;
  // One batch placed: when written straight, or formatted as vertex lines.
  std::vector<WorldVertex> placed_batch_;
  double write_seconds_ = 0;
};

// How slabs join into one volume: where each slab's local vertex indices go in the whole
// volume's numbering (Engine::begin_slab), and the counters summed, slab after slab in order.
class SlabJoin {
 public:
  // The next slab starts; its engine numbered `shared_vertices` vertices it does not emit.
  void begin(std::uint64_t shared_vertices) { shared_ = shared_vertices; }
  // Moves the current slab's local indices to the whole volume's, in place. `own_only`: no
  // index refers to a shared vertex (SlabChunk::Call::own_vertices_only).
  void relocate(Polygon* polygons, std::uint32_t count, bool own_only) const;
  // What relocate() adds to an index that refers to none of the shared vertices, modulo 2^32.
  std::uint32_t own_offset() const { return static_cast<std::uint32_t>(slab_base_ - shared_); }
  // The current slab has ended; the next one is current.
  void end(const SlabSummary& summary);

  // Vertices of the slabs ended so far: the whole-volume index of the next slab's first own
  // vertex.
  std::uint64_t vertices_before() const { return slab_base_; }
  // The counters of the slabs ended so far, as one engine over them would count.
  const EngineCounters& counters() const { return counters_; }

 private:
  std::uint64_t slab_base_ = 0;    // vertices of the slabs before the current one
  std::uint64_t shared_base_ = 0;  // where the current slab's shared vertices start
  std::uint64_t shared_ = 0;       // the current slab's shared vertex count
  EngineCounters counters_;
};

// Replays slabs, in order, into a mesh writer, moving each slab's local vertex indices to the
// whole volume's numbering, and sums their counters.
class SlabReplay {
 public:
  // `after`: the slabs before the first one replayed here, when their output is written by
  // other processes (mvox-mpi); the writer then numbers its vertices from
  // after.vertices_before() on (MeshWriterOptions::part).
  // `mesh` null: the slabs recorded nothing (SlabRecorder without placement); only their
  // counters are summed.
  explicit SlabReplay(MeshWriter* mesh, const SlabJoin& after = {}) : mesh_(mesh), join_(after) {}

  // Replays one chunk of the current slab; after its last chunk the next slab is current.
  // Moves the chunk's vertex indices in place. Returns the writer's status (sink_refused: the
  // writer holds the error).
  Status replay(SlabChunk& chunk);
  const SlabJoin& join() const { return join_; }
  const EngineCounters& counters() const { return join_.counters(); }

  // The calls of the current slab, given as its engine makes them instead of from a chunk
  // (SlabRecorder::Handover::writer): each does what replay() does with a recorded call.
  Status placed_vertices(const WorldVertex* vertices, std::size_t count);
  Status vertices(const Vertex* vertices, const glm::vec3* normals, std::size_t count);
  // Polygons that may refer to shared vertices are copied to be moved; the others are moved
  // as the writer formats them.
  Status polygons(const Polygon* polygons, std::uint32_t count, bool own_only);
  Status geometry(const PolygonGeometry* polygons, std::size_t count);

 private:
  MeshWriter* mesh_;
  SlabJoin join_;
  std::vector<Polygon> moved_;  // a batch of polygons(), moved
};

}  // namespace mvox
