#include "pipeline/slab_recorder.h"

#include <algorithm>

#include "pipeline/stopwatch.h"
#include "write/mesh/binary_records.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {

void SlabChunk::clear() {
  calls.clear();
  placed_count = 0;
  vertices.clear();
  normals.clear();
  polygons.clear();
  geometry.clear();
  formatted.clear();
  formatted_runs.clear();
  first = false;
  shared_vertices = 0;
  last = false;
  summary = SlabSummary();
}

namespace {

// Room for kChunkBytes of T and one batch more.
template <class T>
std::size_t capacity_for(std::uint32_t batch) {
  return SlabRecorder::kChunkBytes / sizeof(T) + batch;
}

// The shortest vertex line a text format makes: ASCII PLY's "0 0 0\n".
constexpr std::size_t kShortestVertexText = 6;

// Every call counts its own size in SlabChunk::bytes(), and a call of the engine's batches at
// least one vertex or polygon too (the engine sends no empty batch); a vertex_count call keeps
// nothing else, a formatted_vertices call one line at least. A chunk handed on at kChunkBytes
// holds fewer calls than that many bytes allow, and the geometry that follows its last polygon
// batch.
std::size_t calls_capacity(bool formatted_faces, bool formatted_vertices) {
  const std::size_t smallest_vertex = formatted_vertices ? kShortestVertexText : sizeof(Vertex);
  const std::size_t smallest =
      sizeof(SlabChunk::Call) + (formatted_faces ? 0 : std::min(smallest_vertex, sizeof(Polygon)));
  return SlabRecorder::kChunkBytes / smallest + 3;
}

// A formatted_faces call keeps one triangle at least, a formatted_vertices call one line.
std::size_t formatted_runs_capacity(bool formatted_vertices) {
  const std::size_t smallest = formatted_vertices ? kShortestVertexText : kStlTriangleBytes;
  return SlabRecorder::kChunkBytes / (sizeof(SlabChunk::Call) + smallest) + 3;
}

// Room for a chunk of formatted records and one batch's more.
std::size_t formatted_capacity(std::uint32_t batch, std::size_t bytes_per_item) {
  return SlabRecorder::kChunkBytes + batch * bytes_per_item;
}

}  // namespace

// With formatted faces a chunk keeps records, vertex counts and, while it is formatted, one
// polygon batch. It keeps the engine's batches only for a slab whose formatter refused one (or
// a vertex out of float's range), which the writer then refuses in turn: those arrays are not
// reserved and grow if that happens, in a run that fails.
void SlabChunk::reserve(const EngineOptions& engine, std::size_t formatted_bytes_per_polygon,
                        std::size_t formatted_bytes_per_vertex) {
  const bool formatting = formatted_bytes_per_polygon > 0;
  const bool vertex_text = formatted_bytes_per_vertex > 0;
  calls.reserve(calls_capacity(formatting, vertex_text));
  if (formatting) {
    polygons.reserve(engine.polygons_per_batch);
    formatted.reserve_capacity(
        formatted_capacity(engine.polygons_per_batch, formatted_bytes_per_polygon));
    formatted_runs.reserve(formatted_runs_capacity(false));
    return;
  }
  if (vertex_text) {
    formatted.reserve_capacity(
        formatted_capacity(engine.vertices_per_batch, formatted_bytes_per_vertex));
    formatted_runs.reserve(formatted_runs_capacity(true));
  } else {
    placed.reserve(capacity_for<WorldVertex>(engine.vertices_per_batch));
  }
  polygons.reserve(capacity_for<Polygon>(engine.polygons_per_batch));
  if (engine.polygon_geometry)
    geometry.reserve(capacity_for<PolygonGeometry>(engine.polygons_per_batch));
}

std::size_t SlabChunk::reserved_bytes(const EngineOptions& engine,
                                      std::size_t formatted_bytes_per_polygon,
                                      std::size_t formatted_bytes_per_vertex) {
  const bool formatting = formatted_bytes_per_polygon > 0;
  const bool vertex_text = formatted_bytes_per_vertex > 0;
  std::size_t bytes = calls_capacity(formatting, vertex_text) * sizeof(SlabChunk::Call);
  if (formatting)
    return bytes + std::size_t{engine.polygons_per_batch} * sizeof(Polygon) +
           formatted_capacity(engine.polygons_per_batch, formatted_bytes_per_polygon) +
           formatted_runs_capacity(false) * sizeof(FormattedRun);
  if (vertex_text)
    bytes += formatted_capacity(engine.vertices_per_batch, formatted_bytes_per_vertex) +
             formatted_runs_capacity(true) * sizeof(FormattedRun);
  else
    bytes += capacity_for<WorldVertex>(engine.vertices_per_batch) * sizeof(WorldVertex);
  bytes += capacity_for<Polygon>(engine.polygons_per_batch) * sizeof(Polygon);
  if (engine.polygon_geometry)
    bytes += capacity_for<PolygonGeometry>(engine.polygons_per_batch) * sizeof(PolygonGeometry);
  return bytes;
}

SlabRecorder::SlabRecorder(Handover& handover, const VertexPlacement* placement,
                           const VertexNormals* normals, bool geometry_follows,
                           FaceFormatter* formatter, VertexTextFormatter* vertex_text)
    : handover_(handover),
      placement_(placement),
      normals_(normals),
      geometry_follows_(geometry_follows),
      formatter_(placement ? formatter : nullptr),
      vertex_text_(placement ? vertex_text : nullptr) {}

bool SlabRecorder::start(std::uint64_t shared_vertices) {
  own_only_ = false;
  formatting_ = formatter_ != nullptr;
  if (formatting_) formatter_->start_slab(shared_vertices);
  chunk_ = handover_.take();
  if (!chunk_) return false;
  chunk_->first = true;
  chunk_->shared_vertices = shared_vertices;
  return true;
}

void SlabRecorder::end(const SlabSummary& summary) {
  chunk_->last = true;
  chunk_->summary = summary;
  handover_.full(chunk_);
  chunk_ = nullptr;
}

bool SlabRecorder::after_call() {
  if (chunk_->bytes() < kChunkBytes) return true;
  handover_.full(chunk_);
  chunk_ = handover_.take();
  return chunk_ != nullptr;
}

Status SlabRecorder::written(Status status, double seconds) {
  write_seconds_ += seconds;
  if (status != Status::ok) handover_.refused(status);
  return status;
}

// The engine is built without exceptions: a failed allocation here must not unwind through it,
// so every call catches and refuses (the worker then reports the engine's sink_refused).
bool SlabRecorder::place_batch(const Vertex* vertices, const glm::vec3* normals,
                               std::size_t count) {
  if (placed_batch_.size() < count) placed_batch_.resize(count);
  return placement_->place(vertices, normals, count, placed_batch_.data()) == count;
}

Status SlabRecorder::consume_vertices(const Vertex* vertices, std::size_t count) {
  if (!placement_) return Status::ok;
  try {
    const glm::vec3* normals = nullptr;
    if (normals_) {
      if (batch_normals_.size() < count) batch_normals_.resize(count);
      normals_->compute(vertices, count, batch_normals_.data());
      normals = batch_normals_.data();
    }
    if (SlabReplay* writer = handover_.writer(chunk_)) {
      const auto start = Clock::now();
      // A vertex outside float's range is left for the writer, which refuses it by its index.
      const Status status = place_batch(vertices, normals, count)
                                ? writer->placed_vertices(placed_batch_.data(), count)
                                : writer->vertices(vertices, normals, count);
      return written(status, seconds_since(start));
    }
    if (formatting_) {
      // The writer keeps only the count; the placement checks that every vertex is in range.
      if (place_batch(vertices, normals, count) &&
          formatter_->consume_vertex_count(count) == Status::ok) {
        chunk_->calls.push_back(
            {SlabChunk::Kind::vertex_count, own_only_, static_cast<std::uint32_t>(count)});
        return after_call() ? Status::ok : Status::sink_refused;
      }
      formatting_ = false;
    }
    if (vertex_text_) {
      if (place_batch(vertices, normals, count)) {
        SlabChunk& chunk = *chunk_;
        const std::size_t bytes_before = chunk.formatted.size();
        try {
          vertex_text_->format(placed_batch_.data(), count, chunk.formatted);
        } catch (...) {
          chunk.formatted.truncate(bytes_before);  // the chunk stays whole; the run fails
          throw;
        }
        chunk.calls.push_back(
            {SlabChunk::Kind::formatted_vertices, own_only_, static_cast<std::uint32_t>(count)});
        chunk.formatted_runs.push_back(
            {static_cast<std::uint32_t>(count),
             static_cast<std::uint32_t>(chunk.formatted.size() - bytes_before)});
        return after_call() ? Status::ok : Status::sink_refused;
      }
    } else {
      const std::size_t first = chunk_->placed_count;
      // Room was reserved for a full chunk and one batch more (SlabChunk::reserve); grown only
      // as far as it is used, and left unwritten until place() writes it.
      if (chunk_->placed.size() < first + count) chunk_->placed.resize(first + count);
      if (placement_->place(vertices, normals, count, &chunk_->placed[first]) == count) {
        chunk_->placed_count += count;
        chunk_->calls.push_back(
            {SlabChunk::Kind::placed_vertices, own_only_, static_cast<std::uint32_t>(count)});
        return after_call() ? Status::ok : Status::sink_refused;
      }
    }
    // A vertex outside float's range: the batch is kept as the engine made it, for the writer,
    // which refuses it naming the vertex by its index in the whole mesh, as with one thread.
    record(SlabChunk::Kind::vertices, chunk_->vertices, vertices, count);
    if (normals) chunk_->normals.insert(chunk_->normals.end(), normals, normals + count);
    return after_call() ? Status::ok : Status::sink_refused;
  } catch (...) {
    return Status::sink_refused;
  }
}

template <class Item>
void SlabRecorder::record(SlabChunk::Kind kind, std::vector<Item>& items, const Item* batch,
                          std::size_t count) {
  chunk_->calls.push_back({kind, own_only_, static_cast<std::uint32_t>(count)});
  items.insert(items.end(), batch, batch + count);
}

Status SlabRecorder::consume_polygons(const Polygon* polygons, std::size_t count) {
  if (!placement_) return Status::ok;
  try {
    if (SlabReplay* writer = handover_.writer(chunk_)) {
      const auto start = Clock::now();
      const Status status =
          writer->polygons(polygons, static_cast<std::uint32_t>(count), own_only_);
      return written(status, seconds_since(start));
    }
    record(SlabChunk::Kind::polygons, chunk_->polygons, polygons, count);
    // A geometry batch follows at once when the engine sends one: the chunk is handed on after
    // it, so that the pair stays in one chunk. Otherwise now: a layer of cubes can send many
    // polygon batches with no vertex batch between them.
    if (geometry_follows_) return Status::ok;
    return after_call() ? Status::ok : Status::sink_refused;
  } catch (...) {
    return Status::sink_refused;
  }
}

Status SlabRecorder::consume_polygon_geometry(const PolygonGeometry* polygons, std::size_t count) {
  if (!placement_) return Status::ok;
  try {
    // If the turn came between the polygons and their geometry, the polygons were recorded and
    // are written first (writer()): the writer keeps them until their geometry comes.
    if (SlabReplay* writer = handover_.writer(chunk_)) {
      const auto start = Clock::now();
      return written(writer->geometry(polygons, count), seconds_since(start));
    }
    if (!formatting_ || !format_recorded_batch(polygons, count))
      record(SlabChunk::Kind::geometry, chunk_->geometry, polygons, count);
    return after_call() ? Status::ok : Status::sink_refused;
  } catch (...) {
    return Status::sink_refused;
  }
}

bool SlabRecorder::format_recorded_batch(const PolygonGeometry* geometry, std::size_t count) {
  // The polygons came just before, in the same chunk (geometry_follows_).
  SlabChunk& chunk = *chunk_;
  if (chunk.calls.empty() || chunk.calls.back().kind != SlabChunk::Kind::polygons ||
      chunk.calls.back().count != count || chunk.polygons.size() < count) {
    formatting_ = false;
    return false;
  }
  const std::size_t polygons_kept = chunk.polygons.size() - count;
  const std::size_t bytes_before = chunk.formatted.size();
  const std::uint64_t faces_before = formatter_->faces_written();
  formatter_->format_into(&chunk.formatted);
  if (formatter_->consume_polygons(chunk.polygons.data() + polygons_kept, count) != Status::ok ||
      formatter_->consume_polygon_geometry(geometry, count) != Status::ok) {
    chunk.formatted.truncate(bytes_before);
    formatting_ = false;
    return false;
  }
  chunk.polygons.resize(polygons_kept);
  chunk.calls.back().kind = SlabChunk::Kind::formatted_faces;
  chunk.formatted_runs.push_back(
      {static_cast<std::uint32_t>(formatter_->faces_written() - faces_before),
       static_cast<std::uint32_t>(chunk.formatted.size() - bytes_before)});
  return true;
}

void SlabJoin::relocate(Polygon* polygons, std::uint32_t count, bool own_only) const {
  // Local index i < shared: the previous slab's last slice's vertex shared_base + i; any
  // other: this slab's own vertex slab_base + i - shared. Modulo 2^32, as the engine gives
  // indices (mvox/mesh.h): the writer makes them whole.
  const auto own = static_cast<std::uint32_t>(slab_base_ - shared_);
  if (own_only) {
    for (std::uint32_t i = 0; i < count; ++i)
      for (int k = 0; k < polygons[i].vertex_count; ++k) polygons[i].vertices[k] += own;
    return;
  }
  // Every slot, past the size too (the writer never reads those), and without a branch: which
  // of the two a slot is does not follow a pattern, and a branch on it was mispredicted often
  // enough to make this loop 1% of a slab worker's time.
  const auto shared = static_cast<std::uint32_t>(shared_);
  const auto to_shared = static_cast<std::uint32_t>(shared_base_) - own;
  for (std::uint32_t i = 0; i < count; ++i)
    for (std::uint32_t& slot : polygons[i].vertices) slot += own + (slot < shared ? to_shared : 0u);
}

void SlabJoin::end(const SlabSummary& summary) {
  const EngineCounters& c = summary.counters;
  const std::uint64_t emitted = c.vertices - c.shared_vertices;
  shared_base_ = slab_base_ + summary.last_slice_first_vertex - c.shared_vertices;
  slab_base_ += emitted;
  counters_.slices += c.slices;
  counters_.inner_voxels += c.inner_voxels;
  counters_.vertices += emitted;
  counters_.polygons += c.polygons;
  for (int size = 0; size <= kMaxPolygonVertices; ++size)
    counters_.polygons_by_size[size] += c.polygons_by_size[size];
  shared_ = 0;
}

Status SlabReplay::replay(SlabChunk& chunk) {
  if (chunk.first) join_.begin(chunk.shared_vertices);
  if (!mesh_ && !chunk.calls.empty())
    return Status::invalid_argument;  // recorded output with nowhere to go: a caller's mistake
  std::size_t placed_at = 0, vertex_at = 0, polygon_at = 0, geometry_at = 0;
  std::size_t formatted_at = 0, run_at = 0;
  for (const SlabChunk::Call& call : chunk.calls) {
    Status status = Status::ok;
    switch (call.kind) {
      case SlabChunk::Kind::placed_vertices:
        status = mesh_->consume_placed_vertices(chunk.placed.data() + placed_at, call.count);
        placed_at += call.count;
        break;
      case SlabChunk::Kind::vertices:
        status = mesh_->consume_vertices_with_normals(
            chunk.vertices.data() + vertex_at,
            chunk.normals.empty() ? nullptr : chunk.normals.data() + vertex_at, call.count);
        vertex_at += call.count;
        break;
      case SlabChunk::Kind::polygons: {
        Polygon* polygons = chunk.polygons.data() + polygon_at;
        // Polygons of the slab's own vertices are moved by one offset, as they are formatted;
        // those of its first layer here, by the rule for shared vertices.
        if (call.own_vertices_only) {
          status = mesh_->consume_moved_polygons(polygons, call.count, join_.own_offset());
        } else {
          join_.relocate(polygons, call.count, false);
          status = mesh_->consume_polygons(polygons, call.count);
        }
        polygon_at += call.count;
        break;
      }
      case SlabChunk::Kind::geometry:
        status = mesh_->consume_polygon_geometry(chunk.geometry.data() + geometry_at, call.count);
        geometry_at += call.count;
        break;
      case SlabChunk::Kind::vertex_count: status = mesh_->consume_vertex_count(call.count); break;
      case SlabChunk::Kind::formatted_faces: {
        const SlabChunk::FormattedRun& run = chunk.formatted_runs[run_at++];
        status = mesh_->consume_formatted_faces(chunk.formatted.data() + formatted_at, run.bytes,
                                                call.count, run.count);
        formatted_at += run.bytes;
        break;
      }
      case SlabChunk::Kind::formatted_vertices: {
        const SlabChunk::FormattedRun& run = chunk.formatted_runs[run_at++];
        status = mesh_->consume_formatted_vertices(chunk.formatted.data() + formatted_at, run.bytes,
                                                   call.count);
        formatted_at += run.bytes;
        break;
      }
    }
    if (status != Status::ok) return status;
  }
  if (chunk.last) join_.end(chunk.summary);
  return Status::ok;
}

Status SlabReplay::placed_vertices(const WorldVertex* vertices, std::size_t count) {
  return mesh_->consume_placed_vertices(vertices, count);
}

Status SlabReplay::vertices(const Vertex* vertices, const glm::vec3* normals, std::size_t count) {
  return mesh_->consume_vertices_with_normals(vertices, normals, count);
}

Status SlabReplay::polygons(const Polygon* polygons, std::uint32_t count, bool own_only) {
  if (own_only) return mesh_->consume_moved_polygons(polygons, count, join_.own_offset());
  moved_.assign(polygons, polygons + count);
  join_.relocate(moved_.data(), count, false);
  return mesh_->consume_polygons(moved_.data(), count);
}

Status SlabReplay::geometry(const PolygonGeometry* polygons, std::size_t count) {
  return mesh_->consume_polygon_geometry(polygons, count);
}

}  // namespace mvox
