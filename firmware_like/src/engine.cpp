// The streaming engine. For each slice s:
//   PASS 1  classify slice s into bit rows (classify.h);
//   PASS 2  find the vertices on the x- and y-edges of slice s and on the z-edges between slices
//           s-1 and s, number them in that order and send them to the sink (edge_plane.h);
//   PASS 3  find the polygons of every cube between slices s-1 and s, which that slice
//           completes, and send them: by table lookup (fast) or from the literal merge passes.
//           The fast engine walks the cubes in the order PASS 2 numbered the vertices, so it
//           knows each vertex's index by running counts; the literal engine asks the edge planes.
// Marching cubes runs the same passes with its own table of triangles (PASS 3) and moves each
// vertex along its edge to the interpolated crossing (edge_interpolation.h); marching voxels
// moves its vertices so too when options.interpolate asks.
// Slices -1 and D (one past the last) are all outer, so every surface closes.
#include "mvox/engine.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>

#include "bit_rows.h"
#include "case_table.h"
#include "classify.h"
#include "cpu_features.h"
#include "cube.h"
#include "edge_interpolation.h"
#include "edge_plane.h"
#include "literal_layers.h"
#include "marching_cubes_table.h"
#include "word_configs.h"

#if MVOX_HAVE_AVX2_PATH
#include <immintrin.h>
#endif

namespace mvox {

using detail::EngineState;

namespace {

// Slices with more edges than this in a plane are refused: plane counters are 32-bit, and a
// layer's polygons refer to vertices of at most six planes (x- and y-edges of two slices, the
// z-edges below each), which must stay within kMaxVerticesBack of each other so that indices
// modulo 2^32 can be made whole again (mesh.h). About 26,700 x 26,700 voxels.
constexpr std::uint64_t kMaxEdgesPerPlane = (kMaxVerticesBack - 1) / 6;

constexpr std::uint64_t align_up(std::uint64_t bytes) {
  return (bytes + kWorkspaceAlignment - 1) & ~std::uint64_t{kWorkspaceAlignment - 1};
}

// Where each buffer lives in the workspace. One function computes it both for
// engine_workspace_bytes() and for init(), so the two can never disagree.
struct Layout {
  std::size_t state = 0;
  std::size_t inner[2] = {};
  std::size_t occupied[2] = {};
  std::size_t zero_row = 0;
  std::size_t x_bits[2] = {}, x_prefix[2] = {};
  std::size_t y_bits[2] = {}, y_prefix[2] = {};
  std::size_t z_bits = 0, z_prefix = 0;
  std::size_t vertices = 0;
  std::size_t polygons = 0;
  std::size_t geometry = 0;
  std::size_t literal = 0;
  std::size_t samples[2] = {};
  std::size_t total = 0;
};

// Marching cubes always places its vertices at the interpolated crossing; marching voxels when
// asked.
bool interpolates(const EngineOptions& options) {
  return options.method == SurfaceMethod::cubes || options.interpolate;
}

bool options_valid(const EngineOptions& options) {
  if (options.method == SurfaceMethod::cubes)
    return options.kind == EngineKind::fast && options.rule == SurfaceRule::merge_rules &&
           options.vertices_per_batch >= 1 && options.polygons_per_batch >= 1;
  return options.method == SurfaceMethod::voxels &&
         (options.kind == EngineKind::fast || options.kind == EngineKind::literal) &&
         (options.rule == SurfaceRule::merge_rules || options.rule == SurfaceRule::paper_table1) &&
         options.vertices_per_batch >= 1 && options.polygons_per_batch >= 1;
}

}  // namespace

struct detail::EngineState {
  EngineOptions options;
  Thresholds thresholds;
  PolygonSink* sink = nullptr;
  const CaseTable* table = nullptr;
  std::uint32_t row_words = 0;
  std::uint64_t* inner[2] = {};    // bit rows of slice s in slot s & 1
  std::uint8_t* occupied[2] = {};  // per bit row of each slot: has it an inner voxel?
  const std::uint64_t* zero_row = nullptr;
  EdgePlane x_edges[2];  // x-edges of the slice in each slot
  EdgePlane y_edges[2];  // y-edges of the slice in each slot (height + 1 rows)
  EdgePlane z_edges;     // z-edges between the two slots' slices
  Vertex* vertex_batch = nullptr;
  Polygon* polygon_batch = nullptr;
  PolygonGeometry* geometry_batch = nullptr;  // parallel to polygon_batch; null unless asked for
  LiteralLayers literal;
  EdgeInterpolation interpolation;  // marching cubes only
  bool interpolate = false;
  bool use_avx2 = false;  // run the AVX2 hot loops (cpu_features.h); decided once by init()

  const std::uint64_t* row(int slot, std::int64_t y, std::uint32_t height) const {
    if (y < 0 || y >= static_cast<std::int64_t>(height)) return zero_row;
    return inner[slot] + static_cast<std::size_t>(y) * row_words;
  }

  bool row_occupied(int slot, std::int64_t y, std::uint32_t height) const {
    return y >= 0 && y < static_cast<std::int64_t>(height) && occupied[slot][y];
  }
};

namespace {

bool compute_layout(std::uint32_t width, std::uint32_t height, const EngineOptions& options,
                    Layout* layout) {
  if (width == 0 || height == 0 || !options_valid(options)) return false;
  // Checked in 64 bits before any 32-bit arithmetic on the dimensions: this bound keeps
  // width + 2, height + 1 and every plane's vertex count far below 2^32.
  if ((std::uint64_t{width} + 2) * (std::uint64_t{height} + 1) > kMaxEdgesPerPlane) return false;
  const std::uint64_t words = padded_row_words(width);
  std::uint64_t offset = 0;  // 64-bit so that a 32-bit size_t cannot wrap; checked at the end
  auto take = [&offset](std::uint64_t bytes) {
    const std::uint64_t start = offset;
    offset += align_up(bytes);
    return static_cast<std::size_t>(start);
  };
  auto words_bytes = [words](std::uint64_t rows) { return rows * words * sizeof(std::uint64_t); };
  auto prefix_bytes = [words](std::uint64_t rows) { return rows * words * sizeof(std::uint32_t); };
  layout->state = take(sizeof(EngineState));
  for (int slot = 0; slot < 2; ++slot) {
    layout->inner[slot] = take(words_bytes(height));
    layout->occupied[slot] = take(height);
  }
  layout->zero_row = take(words_bytes(1));
  // The edge planes' bits and prefix counts serve only the literal engine's rank queries
  // (cube_edge_index); the fast engine numbers vertices by running counts (for_each_surface_cube).
  const bool planes = options.kind == EngineKind::literal;
  for (int slot = 0; slot < 2; ++slot) {
    layout->x_bits[slot] = take(planes ? words_bytes(height) : 0);
    layout->x_prefix[slot] = take(planes ? prefix_bytes(height) : 0);
    layout->y_bits[slot] = take(planes ? words_bytes(std::uint64_t{height} + 1) : 0);
    layout->y_prefix[slot] = take(planes ? prefix_bytes(std::uint64_t{height} + 1) : 0);
  }
  layout->z_bits = take(planes ? words_bytes(height) : 0);
  layout->z_prefix = take(planes ? prefix_bytes(height) : 0);
  layout->vertices = take(std::uint64_t{options.vertices_per_batch} * sizeof(Vertex));
  layout->polygons = take(std::uint64_t{options.polygons_per_batch} * sizeof(Polygon));
  layout->geometry = take(options.polygon_geometry
                              ? std::uint64_t{options.polygons_per_batch} * sizeof(PolygonGeometry)
                              : 0);
  layout->literal =
      take(options.kind == EngineKind::literal ? LiteralLayers::bytes(width, height) : 0);
  for (int slot = 0; slot < 2; ++slot)
    layout->samples[slot] =
        take(interpolates(options) ? EdgeInterpolation::slab_bytes(width, height) : 0);
  if (offset > SIZE_MAX / 2) return false;
  layout->total = static_cast<std::size_t>(offset);
  return true;
}

}  // namespace

std::size_t engine_workspace_bytes(std::uint32_t width, std::uint32_t height,
                                   const EngineOptions& options) {
  Layout layout;
  return compute_layout(width, height, options, &layout) ? layout.total : 0;
}

void detail::use_baseline_loops(Engine& engine) {
  if (engine.state_) engine.state_->use_avx2 = false;
}

void detail::number_vertices_from(Engine& engine, std::uint64_t first) {
  if (engine.counters_.slices == 0) engine.counters_.vertices = first;
}

Status Engine::fail(Status status) {
  failure_ = status;
  return status;
}

Status Engine::init(void* workspace, std::size_t workspace_bytes, std::uint32_t width,
                    std::uint32_t height, double threshold, const EngineOptions& options,
                    PolygonSink* sink) {
  state_ = nullptr;
  failure_ = Status::not_initialised;
  counters_ = EngineCounters();
  first_slice_ = 0;
  Layout layout;
  if (!workspace || !sink || threshold != threshold ||
      !compute_layout(width, height, options, &layout))
    return Status::invalid_argument;
  if (reinterpret_cast<std::uintptr_t>(workspace) % kWorkspaceAlignment != 0)
    return Status::workspace_misaligned;
  if (workspace_bytes < layout.total) return Status::workspace_too_small;

  char* base = static_cast<char*>(workspace);
  EngineState* state = new (base + layout.state) EngineState();
  state->options = options;
  state->thresholds = make_thresholds(threshold);
  state->sink = sink;
  state->table = &case_table(options.rule);
  state->use_avx2 = cpu_has_avx2_bmi2();
  state->row_words = padded_row_words(width);
  const std::uint32_t words = state->row_words;
  // Only the literal engine stores the planes' bits and prefix counts (compute_layout).
  auto plane = [&](std::size_t bits, std::size_t prefix, std::uint32_t rows) {
    EdgePlane result;
    if (options.kind == EngineKind::literal) {
      result.bits = reinterpret_cast<std::uint64_t*>(base + bits);
      result.prefix = reinterpret_cast<std::uint32_t*>(base + prefix);
    }
    result.rows = rows;
    result.row_words = words;
    return result;
  };
  for (int slot = 0; slot < 2; ++slot) {
    state->inner[slot] = reinterpret_cast<std::uint64_t*>(base + layout.inner[slot]);
    state->occupied[slot] = reinterpret_cast<std::uint8_t*>(base + layout.occupied[slot]);
    state->x_edges[slot] = plane(layout.x_bits[slot], layout.x_prefix[slot], height);
    state->y_edges[slot] = plane(layout.y_bits[slot], layout.y_prefix[slot], height + 1);
  }
  state->z_edges = plane(layout.z_bits, layout.z_prefix, height);
  std::uint64_t* zero_row = reinterpret_cast<std::uint64_t*>(base + layout.zero_row);
  std::memset(zero_row, 0, words * sizeof(std::uint64_t));
  state->zero_row = zero_row;
  // Slot 1 stands for slice -1 when slice 0 arrives: all outer.
  std::memset(state->inner[1], 0, std::size_t{height} * words * sizeof(std::uint64_t));
  std::memset(state->occupied[1], 0, height);
  state->vertex_batch = reinterpret_cast<Vertex*>(base + layout.vertices);
  state->polygon_batch = reinterpret_cast<Polygon*>(base + layout.polygons);
  if (options.polygon_geometry)
    state->geometry_batch = reinterpret_cast<PolygonGeometry*>(base + layout.geometry);
  if (options.kind == EngineKind::literal)
    state->literal.init(base + layout.literal, width, height);
  if (interpolates(options)) {
    state->interpolate = true;
    // Marching voxels' vertices stay off the voxel centres, so that their polygons can always
    // be split into triangles (EdgeInterpolation::init).
    const float margin = options.method == SurfaceMethod::voxels ? 0.01f : 0.0f;
    state->interpolation.init(reinterpret_cast<unsigned char*>(base + layout.samples[0]),
                              reinterpret_cast<unsigned char*>(base + layout.samples[1]), width,
                              height, threshold, margin);
  }

  state_ = state;
  width_ = width;
  height_ = height;
  failure_ = Status::ok;
  return Status::ok;
}

// ---------------------------------------------------------------------------------------------
// Output batching.

namespace {

// Batches one layer's vertices and polygons for the sink. The batch fills and the layer's counts
// live in the emitter, not in the engine state: the emitter is a local whose address never
// escapes, so the compiler keeps them in registers through the hot loops (through the state they
// would be reloaded after every store into a batch, which might alias them). Both batches are
// empty between layers, and the counts reach the engine's counters however the layer ends.
class Emitter {
 public:
  Emitter(EngineState& state, EngineCounters& counters)
      : state_(state),
        counters_(counters),
        vertices_(state.vertex_batch),
        vertex_capacity_(state.options.vertices_per_batch),
        vertex_count_(counters.vertices),
        polygons_(state.polygon_batch),
        geometry_(state.geometry_batch),
        polygon_capacity_(state.options.polygons_per_batch),
        interpolation_(state.interpolate ? &state.interpolation : nullptr) {}

  Emitter(const Emitter&) = delete;
  Emitter& operator=(const Emitter&) = delete;

  ~Emitter() {
    counters_.vertices = vertex_count_;
    for (int size = 0; size <= kMaxPolygonVertices; ++size) {
      counters_.polygons += polygons_by_size_[size];
      counters_.polygons_by_size[size] += polygons_by_size_[size];
    }
  }

  // The one place a vertex is produced, numbered on without limit (polygons carry the index
  // modulo 2^32, mesh.h). Returns false when the sink refused; status() says so.
  bool vertex(float x, float y, float z, Axis axis, bool inner_is_lower) {
    Vertex& v = vertices_[vertex_fill_++];
    v.x = x;
    v.y = y;
    v.z = z;
    v.axis = axis;
    v.inner_is_lower = inner_is_lower;
    if (interpolation_) interpolation_->place(v);
    ++vertex_count_;
    return vertex_fill_ < vertex_capacity_ || flush_vertices();
  }

  // Where the caller may write up to `count` vertices itself, then hand them over with
  // commit_vertices(): null unless the batch has room for all of them (so no vertex among them
  // needs a flush) and vertices stay at the midpoints.
  Vertex* reserve_vertices(std::uint32_t count) const {
    const bool room = vertex_capacity_ - vertex_fill_ >= count && !interpolation_;
    return room ? vertices_ + vertex_fill_ : nullptr;
  }

  // The `count` vertices written at reserve_vertices(); flushes a full batch as vertex() does.
  bool commit_vertices(std::uint32_t count) {
    vertex_fill_ += count;
    vertex_count_ += count;
    return vertex_fill_ < vertex_capacity_ || flush_vertices();
  }

  Polygon& next_polygon() { return polygons_[polygon_fill_]; }
  // Null unless the options ask for polygons by value.
  PolygonGeometry* next_geometry() { return geometry_ ? &geometry_[polygon_fill_] : nullptr; }
  // Where vertex() places a vertex: the polygons sent by value must use the same positions.
  void place(Vertex& vertex) const {
    if (interpolation_) interpolation_->place(vertex);
  }

  bool commit_polygon() {
    const Polygon& p = polygons_[polygon_fill_++];
    ++polygons_by_size_[p.vertex_count];
    return polygon_fill_ < polygon_capacity_ || flush_polygons();
  }

  // For a caller that fills the polygon batch itself, keeping the fill and the counts by size in
  // its own locals (emit_layer_fast): the batch, its capacity and its fill so far...
  Polygon* polygon_batch() const { return polygons_; }
  std::uint32_t polygon_capacity() const { return polygon_capacity_; }
  std::uint32_t polygon_fill() const { return polygon_fill_; }
  // ... then its fill and the polygons it added, by size, when it is done or the batch is full.
  void add_polygons(std::uint32_t fill, const std::uint64_t (&by_size)[kMaxPolygonVertices + 1]) {
    polygon_fill_ = fill;
    for (int size = 0; size <= kMaxPolygonVertices; ++size)
      polygons_by_size_[size] += by_size[size];
  }

  bool flush_vertices() {
    if (vertex_fill_ == 0) return true;
    const Status s = state_.sink->consume_vertices(vertices_, vertex_fill_);
    vertex_fill_ = 0;
    return s == Status::ok || stop(Status::sink_refused);
  }

  bool flush_polygons() {
    if (polygon_fill_ == 0) return true;
    Status s = state_.sink->consume_polygons(polygons_, polygon_fill_);
    if (s == Status::ok && geometry_)
      s = state_.sink->consume_polygon_geometry(geometry_, polygon_fill_);
    polygon_fill_ = 0;
    return s == Status::ok || stop(Status::sink_refused);
  }

  Status status() const { return status_; }

 private:
  bool stop(Status status) {
    status_ = status;
    return false;
  }

  EngineState& state_;
  EngineCounters& counters_;
  Status status_ = Status::ok;
  Vertex* const vertices_;
  const std::uint32_t vertex_capacity_;
  std::uint32_t vertex_fill_ = 0;
  std::uint64_t vertex_count_;  // all vertices so far, this layer's included
  Polygon* const polygons_;
  PolygonGeometry* const geometry_;
  const std::uint32_t polygon_capacity_;
  std::uint32_t polygon_fill_ = 0;
  std::uint64_t polygons_by_size_[kMaxPolygonVertices + 1] = {};  // this layer's
  const EdgeInterpolation* const interpolation_;  // marching cubes only: moves each vertex
};

// One family of parallel edges as PASS 2 walks it. Row r of the plane joins bit row `lower` (the
// voxels with the smaller coordinate along `axis`) and bit row `upper`; the edge at column j
// carries a vertex where they differ, at (j + dx, r + dy, z + dz) in voxel units.
struct PlaneGeometry {
  Axis axis;
  float dx, dy, dz;
};

struct EdgeRows {
  const std::uint64_t* lower;
  const std::uint64_t* upper;  // for x-edges the same row as `lower`, read one column on
  bool occupied;               // false when both rows are all outer: no edge has a vertex
};

// The last eight bytes of a vertex (z, axis, inner_is_lower and the padding) of one plane row, for
// either value of inner_is_lower: PASS 2 stores them with one 8-byte copy instead of three
// stores, one of them a read-modify-write of a bool's byte.
class VertexTails {
 public:
  VertexTails(float z, Axis axis) {
    for (int inner = 0; inner < 2; ++inner) {
      unsigned char bytes[8] = {};  // the padding too: zero whichever path wrote the vertex
      const bool inner_is_lower = inner != 0;
      std::memcpy(bytes, &z, sizeof z);
      // Offsets within the tail subtracted first: bytes + offsetof(...) alone would point past
      // the array, which is undefined behaviour even when the result is brought back in bounds
      // (found by fuzz/raw_reader_fuzzer under clang's UndefinedBehaviorSanitizer).
      std::memcpy(bytes + (offsetof(Vertex, axis) - kOffset), &axis, sizeof axis);
      std::memcpy(bytes + (offsetof(Vertex, inner_is_lower) - kOffset), &inner_is_lower,
                  sizeof inner_is_lower);
      std::memcpy(&tails_[inner], bytes, 8);
    }
  }

  void store(Vertex* v, std::uint64_t inner_is_lower) const {
    std::memcpy(reinterpret_cast<unsigned char*>(v) + kOffset, &tails_[inner_is_lower], 8);
  }

 private:
  static constexpr std::size_t kOffset = offsetof(Vertex, z);
  static_assert(sizeof(Vertex) == kOffset + 8 && offsetof(Vertex, inner_is_lower) < sizeof(Vertex),
                "z, axis and inner_is_lower fill a vertex's last eight bytes");
  std::uint64_t tails_[2];
};

// PASS 2 for one plane: a vertex for every edge whose two voxels differ, row by row in increasing
// column, numbered from `first_index`. `rows_of(r)` gives the plane's row r as EdgeRows. Fills
// the plane's bits and prefix counts when it has them (the literal engine's rank queries).
// Without kEmit the vertices are only numbered (counted), none is made: begin_slab() needs the
// previous slab's last plane numbered, and its vertices would only be thrown away.
template <bool kUpperIsNextColumn, bool kEmit = true, typename RowsOf>
bool build_plane(EdgePlane& plane, std::uint32_t first_index, RowsOf rows_of,
                 const PlaneGeometry& geometry, float z, Emitter* emitter) {
  plane.base = first_index;
  const std::uint32_t words = plane.row_words;
  const float vertex_z = z + geometry.dz;
  std::uint32_t count = 0;
  for (std::uint32_t r = 0; r < plane.rows; ++r) {
    const EdgeRows rows = rows_of(r);
    if (!rows.occupied) {  // computational trimming: nothing to read
      if (plane.bits)
        for (std::uint32_t w = 0; w < words; ++w) {
          plane.bits[r * words + w] = 0;
          plane.prefix[r * words + w] = count;
        }
      continue;
    }
    const float y = static_cast<float>(r) + geometry.dy;
    const VertexTails tails(vertex_z, geometry.axis);
    for (std::uint32_t w = 0; w < words; ++w) {
      const std::uint64_t lower = rows.lower[w];
      const std::uint64_t upper =
          kUpperIsNextColumn ? shifted_down(rows.upper, w, words) : rows.upper[w];
      std::uint64_t edges = lower ^ upper;
      if (plane.bits) {
        plane.bits[r * words + w] = edges;
        plane.prefix[r * words + w] = count;
      }
      if (!edges) continue;
      if constexpr (!kEmit) {
        count += static_cast<std::uint32_t>(set_bit_count(edges));
        continue;
      }
      if (Vertex* const first = emitter->reserve_vertices(64)) {
        // The common case: the whole word's vertices written in place, with no test between.
        Vertex* out = first;
        for (; edges; edges &= edges - 1, ++out) {
          const int bit = lowest_set_bit(edges);
          out->x = static_cast<float>(w * 64 + static_cast<std::uint32_t>(bit)) + geometry.dx;
          out->y = y;
          tails.store(out, lower >> bit & 1);
        }
        const std::uint32_t written = static_cast<std::uint32_t>(out - first);
        count += written;
        if (!emitter->commit_vertices(written)) return false;
        continue;
      }
      for (; edges; edges &= edges - 1) {
        const int bit = lowest_set_bit(edges);
        const float x = static_cast<float>(w * 64 + static_cast<std::uint32_t>(bit)) + geometry.dx;
        if (!emitter->vertex(x, y, vertex_z, geometry.axis, (lower >> bit & 1) != 0)) return false;
        ++count;
      }
    }
  }
  plane.count = count;
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Per-slice work.

namespace {

// Vertices on the x- and y-edges of slice `z` (in `slot`), then on the z-edges between the slice
// in the other slot (z - 1) and it. Column j of a padded row is voxel x = j - 1 (bit_rows.h).
// Without kEmit they are numbered, not made, and `emitter` may be null (build_plane).
template <bool kEmit = true>
bool emit_vertices(EngineState& st, int slot, std::uint32_t z, std::uint32_t height,
                   bool with_slice_edges, bool with_z_edges, Emitter* emitter,
                   std::uint64_t first_index) {
  const std::uint32_t words = st.row_words;
  const std::uint64_t* rows = st.inner[slot];
  const std::uint64_t* below = st.inner[slot ^ 1];
  const float fz = static_cast<float>(z);
  std::uint32_t next_index = static_cast<std::uint32_t>(first_index);

  if (with_slice_edges) {
    // x-edge j joins padded columns j and j + 1, voxels x = j - 1 and x = j.
    EdgePlane& xp = st.x_edges[slot];
    if (!build_plane<true, kEmit>(
            xp, next_index,
            [&](std::uint32_t y) {
              const std::uint64_t* row = rows + std::size_t{y} * words;
              return EdgeRows{row, row, st.occupied[slot][y] != 0};
            },
            PlaneGeometry{Axis::x, -0.5f, 0.0f, 0.0f}, fz, emitter))
      return false;
    next_index += xp.count;

    // y-edge row r joins voxel rows r - 1 and r (r = 0 and r = height meet the outside).
    EdgePlane& yp = st.y_edges[slot];
    if (!build_plane<false, kEmit>(
            yp, next_index,
            [&](std::uint32_t r) {
              return EdgeRows{st.row(slot, std::int64_t{r} - 1, height), st.row(slot, r, height),
                              st.row_occupied(slot, std::int64_t{r} - 1, height) ||
                                  st.row_occupied(slot, r, height)};
            },
            PlaneGeometry{Axis::y, -1.0f, -0.5f, 0.0f}, fz, emitter))
      return false;
    next_index += yp.count;
  }
  if (!with_z_edges) return true;

  // z-edges between slice z - 1 (other slot) and slice z.
  return build_plane<false, kEmit>(
      st.z_edges, next_index,
      [&](std::uint32_t y) {
        return EdgeRows{below + std::size_t{y} * words, rows + std::size_t{y} * words,
                        st.occupied[slot ^ 1][y] || st.occupied[slot][y]};
      },
      PlaneGeometry{Axis::z, -1.0f, 0.0f, -0.5f}, fz, emitter);
}

// The global index of the vertex on cube edge `e` (cube.h) of cube (cx, cy) in the layer between
// slot `lo` and slot `hi`, by a rank query on the edge planes. Cube cx holds voxel columns
// cx - 1 and cx, that is padded columns cx and cx + 1; cube cy holds rows cy - 1 and cy.
inline std::uint32_t cube_edge_index(const EngineState& st, int lo, int hi, int e, std::uint32_t cx,
                                     std::uint32_t cy) {
  switch (e) {
    case 0: return st.x_edges[lo].index(cy - 1, cx);
    case 1: return st.x_edges[lo].index(cy, cx);
    case 2: return st.x_edges[hi].index(cy - 1, cx);
    case 3: return st.x_edges[hi].index(cy, cx);
    case 4: return st.y_edges[lo].index(cy, cx);
    case 5: return st.y_edges[lo].index(cy, cx + 1);
    case 6: return st.y_edges[hi].index(cy, cx);
    case 7: return st.y_edges[hi].index(cy, cx + 1);
    case 8: return st.z_edges.index(cy - 1, cx);
    case 9: return st.z_edges.index(cy - 1, cx + 1);
    case 10: return st.z_edges.index(cy, cx);
    default: return st.z_edges.index(cy, cx + 1);
  }
}

// Where the vertex of each cube edge sits relative to the cube's lowest voxel, and which
// corner is the edge's lower end: cube.h's geometry as a table, built at compile time.
struct EdgePlacement {
  float dx, dy, dz;
  Axis axis;
  std::uint8_t low_corner;
};

constexpr EdgePlacement edge_placement(int e) {
  const int low = cube::edge_low_corner(e);
  const int axis = cube::edge_axis(e);
  return {static_cast<float>(cube::corner_bit(low, 0)) + (axis == 0 ? 0.5f : 0.0f),
          static_cast<float>(cube::corner_bit(low, 1)) + (axis == 1 ? 0.5f : 0.0f),
          static_cast<float>(cube::corner_bit(low, 2)) + (axis == 2 ? 0.5f : 0.0f),
          static_cast<Axis>(axis), static_cast<std::uint8_t>(low)};
}

constexpr EdgePlacement kEdgePlacements[cube::kEdges] = {
    edge_placement(0), edge_placement(1), edge_placement(2),  edge_placement(3),
    edge_placement(4), edge_placement(5), edge_placement(6),  edge_placement(7),
    edge_placement(8), edge_placement(9), edge_placement(10), edge_placement(11)};

// The vertex on cube edge `e` of the cube whose lowest voxel is (x0, y0, z0) and whose corners
// are inner where `config` has a bit (cube.h): what PASS 2 emitted for that edge.
inline Vertex cube_edge_vertex(int e, float x0, float y0, float z0, unsigned config) {
  const EdgePlacement& placement = kEdgePlacements[e];
  Vertex v;
  v.x = x0 + placement.dx;
  v.y = y0 + placement.dy;
  v.z = z0 + placement.dz;
  v.axis = placement.axis;
  v.inner_is_lower = (config >> placement.low_corner & 1) != 0;
  return v;
}

// The polygons of cube (cx, cy) between slices z - 1 and z, whose configuration is `config`;
// `edge_index[e]` is the global index of the vertex on cube edge e, for every edge the
// configuration cuts.
bool emit_cube(std::uint32_t cx, std::uint32_t cy, std::uint32_t z, unsigned config,
               const CubePolygons& polygons, const std::uint32_t* edge_index, Emitter& emitter) {
  int offset = 0;
  for (int p = 0; p < polygons.polygon_count; ++p) {
    Polygon& out = emitter.next_polygon();
    out.vertex_count = polygons.polygon_sizes[p];
    for (int i = 0; i < out.vertex_count; ++i)
      out.vertices[i] = edge_index[polygons.edges[offset + i]];
    // Every slot written, as the fast paths write them (copy_polygon): sinks may load all seven
    // (the host's polygon scan, binary PLY's records), and the workspace is not initialised.
    for (int i = out.vertex_count; i < kMaxPolygonVertices; ++i) out.vertices[i] = 0;
    if (PolygonGeometry* geometry = emitter.next_geometry()) {
      // Cube cx holds voxel columns cx - 1 and cx; likewise rows and slices.
      const float x0 = static_cast<float>(cx) - 1.0f, y0 = static_cast<float>(cy) - 1.0f;
      const float z0 = static_cast<float>(z) - 1.0f;
      geometry->vertex_count = out.vertex_count;
      for (int i = 0; i < out.vertex_count; ++i) {
        geometry->vertices[i] = cube_edge_vertex(polygons.edges[offset + i], x0, y0, z0, config);
        emitter.place(geometry->vertices[i]);
      }
    }
    offset += out.vertex_count;
    if (!emitter.commit_polygon()) return false;
  }
  return true;
}

// How far each of the twelve vertex streams of for_each_surface_cube advances past a cube of each
// configuration: 1 on the edges it cuts (cube.h's cut_edges), 0 elsewhere. Whole rows of counts
// make the advance twelve independent adds, which the compiler turns into three vector adds;
// extracting twelve bits of a mask costs several times that.
struct StreamAdvanceTable {
  std::uint32_t advance[256][cube::kEdges];
};

constexpr StreamAdvanceTable build_stream_advance_table() {
  StreamAdvanceTable table{};
  for (unsigned config = 0; config < 256; ++config)
    for (int e = 0; e < cube::kEdges; ++e)
      table.advance[config][e] = cube::cut_edges(config) >> e & 1;
  return table;
}

constexpr StreamAdvanceTable kStreamAdvance = build_stream_advance_table();

// The twelve running counts of for_each_surface_cube, one per cube edge, in an array: the global
// index of the next vertex of each edge's stream.
class EdgeStreams {
 public:
  EdgeStreams(const EngineState& st, int lo, int hi) {
    for (int e = 0; e < 4; ++e) {
      next_[e] = st.x_edges[e < 2 ? lo : hi].base;
      next_[4 + e] = st.y_edges[e < 2 ? lo : hi].base;
      next_[8 + e] = st.z_edges.base;
    }
  }

  // By cube edge: the index of the vertex on each edge the current cube cuts.
  const std::uint32_t* indices() const { return next_; }

  // Past a cube of configuration `config`.
  void advance(unsigned config) {
    const std::uint32_t* advance = kStreamAdvance.advance[config];
    for (int e = 0; e < cube::kEdges; ++e) next_[e] += advance[e];
  }

  // `record` of the current cube into `out`: seven loads and stores, no loop over its size.
  void copy_polygon(const PolygonRecord& record, Polygon& out) const {
    out.vertex_count = record.vertex_count;
    for (int i = 0; i < kMaxPolygonVertices; ++i) out.vertices[i] = next_[record.edges[i]];
  }

 private:
  std::uint32_t next_[cube::kEdges];
};

// PASS 3's walk over the cubes of the layer between slot `lo` and slot `hi`, row by row, in
// increasing x. It visits only cubes whose eight voxels are not all alike (computational
// trimming after Flying Edges), a word of 64 cubes at a time, and calls
// `action(cx, cy, config, streams)` for each, then `streams.advance(config)`; `streams` (an
// EdgeStreams or EdgeStreamsAvx2) holds the global index of the vertex on cube edge e (cube.h)
// for every edge that `config` cuts. Stops when `action` returns false.
//
// The indices come without a rank query. Each cube edge e reads one stream of PASS 2's vertices:
// edge 0 of cube (cx, cy) is the x-edge at column cx of row cy - 1 of the lower slice, edge 5
// the y-edge at column cx + 1 of row cy, and so on (cube_edge_index). As the walk goes through
// the cubes in order, each stream goes through its plane's rows in PASS 2's order, and every
// vertex in it belongs to a cube that cuts e, which is active and visited. So the vertex of a
// cube's edge e is the next one of stream e: a running count, advanced past each cube's cut
// edges. (Columns the walk skips, 0 of y- and z-edges, and row -1, hold no vertex.)
//
// Always inlined (each action has one caller, so no code is duplicated): the action's state then
// stays in its caller's locals, which the compiler keeps in registers; behind a call they would be
// memory that every store into a batch might change.
template <typename Streams, typename CubeAction>
__attribute__((always_inline)) inline bool for_each_surface_cube(const EngineState& st, int lo,
                                                                 int hi, std::uint32_t height,
                                                                 Streams& streams,
                                                                 CubeAction&& action) {
  const std::uint32_t words = st.row_words;
  for (std::uint32_t cy = 0; cy <= height; ++cy) {
    // Computational trimming: four all-outer rows hold no active cube and no vertex, so every
    // stream stays where it is.
    if (!st.row_occupied(lo, std::int64_t{cy} - 1, height) && !st.row_occupied(lo, cy, height) &&
        !st.row_occupied(hi, std::int64_t{cy} - 1, height) && !st.row_occupied(hi, cy, height))
      continue;
    const std::uint64_t* r0 = st.row(lo, std::int64_t{cy} - 1, height);  // corners by=0, bz=0
    const std::uint64_t* r1 = st.row(lo, cy, height);                    // by=1, bz=0
    const std::uint64_t* r2 = st.row(hi, std::int64_t{cy} - 1, height);  // by=0, bz=1
    const std::uint64_t* r3 = st.row(hi, cy, height);                    // by=1, bz=1
    for (std::uint32_t w = 0; w < words; ++w) {
      // Bit cx of a word is the corner at bx = 0; of its shifted copy the corner at bx = 1.
      const std::uint64_t a0 = r0[w], a1 = shifted_down(r0, w, words);
      const std::uint64_t b0 = r1[w], b1 = shifted_down(r1, w, words);
      const std::uint64_t c0 = r2[w], c1 = shifted_down(r2, w, words);
      const std::uint64_t d0 = r3[w], d1 = shifted_down(r3, w, words);
      const std::uint64_t any = a0 | a1 | b0 | b1 | c0 | c1 | d0 | d1;
      const std::uint64_t all = a0 & a1 & b0 & b1 & c0 & c1 & d0 & d1;
      std::uint64_t active = any & ~all;
      if (!active) continue;
      const WordConfigs configs({a0, a1, b0, b1, c0, c1, d0, d1});  // in cube.h's corner order
      for (; active; active &= active - 1) {
        const int bit = lowest_set_bit(active);
        const unsigned config = configs[bit];
        const std::uint32_t cx = w * 64 + static_cast<std::uint32_t>(bit);
        if (!action(cx, cy, config, static_cast<const Streams&>(streams))) return false;
        streams.advance(config);
      }
    }
  }
  return true;
}

#if MVOX_HAVE_AVX2_PATH

// The twelve running counts of for_each_surface_cube in two AVX2 registers (edges 0-7, and
// 8-11 in the low half of the second), so that a polygon's seven indices are gathered from them
// by two lane permutations instead of seven loads and stores.
class EdgeStreamsAvx2 {
 public:
  MVOX_AVX2_HELPER EdgeStreamsAvx2(const EdgeStreams& start)
      : edges0to7_(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(start.indices()))),
        edges8to11_(_mm_loadu_si128(reinterpret_cast<const __m128i*>(start.indices() + 8))) {}

  MVOX_AVX2_HELPER void advance(unsigned config) {
    const std::uint32_t* advance = kStreamAdvance.advance[config];
    edges0to7_ =
        _mm256_add_epi32(edges0to7_, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(advance)));
    edges8to11_ =
        _mm_add_epi32(edges8to11_, _mm_loadu_si128(reinterpret_cast<const __m128i*>(advance + 8)));
  }

  // `record` as the 32 bytes of a Polygon: its vertex_count (with zero padding), then the index
  // of the vertex on each of its seven edges. Lane i of the record widened to 32 bits is edge i
  // (lane 0 the count); its low three bits pick the lane of either register, bit 3 the register.
  MVOX_AVX2_HELPER __m256i polygon(const PolygonRecord& record) const {
    const __m256i lanes =
        _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&record)));
    const __m256i low = _mm256_permutevar8x32_epi32(edges0to7_, lanes);
    // Lanes 4-7 of the high register are never picked: edges 8-11 have low bits 0-3.
    const __m256i high = _mm256_permutevar8x32_epi32(_mm256_castsi128_si256(edges8to11_), lanes);
    const __m256 from_high = _mm256_castsi256_ps(_mm256_slli_epi32(lanes, 28));  // bit 3 to sign
    const __m256i indices = _mm256_castps_si256(
        _mm256_blendv_ps(_mm256_castsi256_ps(low), _mm256_castsi256_ps(high), from_high));
    return _mm256_blend_epi32(indices, lanes, 1);  // lane 0: the vertex count
  }

  // The same polygon as EdgeStreams::copy_polygon gives, in one store (the padding after the
  // count is zero).
  MVOX_AVX2_HELPER void copy_polygon(const PolygonRecord& record, Polygon& out) const {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(&out), polygon(record));
  }

 private:
  __m256i edges0to7_;
  __m128i edges8to11_;
};

static_assert(sizeof(PolygonRecord) == 8 && offsetof(PolygonRecord, edges) == 1,
              "a polygon record is its count and seven edges, one byte each");
static_assert(sizeof(Polygon) == 32 && offsetof(Polygon, vertices) == 4 &&
                  sizeof(Polygon::vertex_count) == 1,
              "a polygon is its count in 4 bytes, then seven 32-bit indices");

#endif

// The polygons of emit_layer_records counted by size in one register: sizes 3 to 6 in four
// 16-bit lanes, and 7 what the rest of the polygons added are. A count in memory,
// `++by_size[size]`, made each polygon wait for the previous one's store whenever the two had the
// same size, as most do (quads): 2% of mvox.extract's time.
class SizeCounts {
 public:
  // Polygons that may be added between two spills without a lane overflowing.
  static constexpr std::uint32_t kMostBetweenSpills = 0xFFFF;

  void add(unsigned size) { packed_ += kLane[size]; }

  // Adds the counts to `by_size`, `polygons` being how many were added since the last spill,
  // and starts again from none.
  void spill(std::uint32_t polygons, std::uint64_t (&by_size)[kMaxPolygonVertices + 1]) {
    std::uint64_t counted = 0;
    for (unsigned size = 3; size < kMaxPolygonVertices; ++size) {
      const std::uint64_t count = packed_ >> (16 * (size - 3)) & 0xFFFF;
      by_size[size] += count;
      counted += count;
    }
    by_size[kMaxPolygonVertices] += polygons - counted;
    packed_ = 0;
  }

 private:
  static_assert(kMaxPolygonVertices == 7, "sizes 3 to 6 in four lanes, 7 the rest");
  static constexpr std::uint64_t kLane[8] = {0, 0, 0, 1, 1ull << 16, 1ull << 32, 1ull << 48, 0};
  std::uint64_t packed_ = 0;
};

// PASS 3, fast, for polygons by index only: each active cube's polygons copied from the case's
// fixed-size records (`streams` as for_each_surface_cube's).
//
// The batch's fill and the counts by polygon size are locals here, handed to the emitter only
// when the batch is full or the layer done. A polygon's vertex_count is a byte store, which the
// compiler must assume may change any object whose address has escaped, as the emitter's has
// (into emit_cube): through the emitter's members, the fill, the batch pointer and the counts
// were reloaded and stored again for every polygon.
template <typename Streams>
__attribute__((always_inline)) inline bool emit_layer_records(const EngineState& st, int lo, int hi,
                                                              std::uint32_t height,
                                                              Streams& streams, Emitter& emitter) {
  const CaseRecords* const records = st.table->records;
  Polygon* const batch = emitter.polygon_batch();
  const std::uint32_t capacity = emitter.polygon_capacity();
  std::uint32_t fill = emitter.polygon_fill();
  std::uint32_t spilled_at = fill;  // the fill when the counts were last spilled
  SizeCounts counts;
  std::uint64_t by_size[kMaxPolygonVertices + 1] = {};
  // A full batch spills the counts; only batches larger than a lane holds need spills between.
  const bool spill_between = capacity > SizeCounts::kMostBetweenSpills;
  const bool ok = for_each_surface_cube(
      st, lo, hi, height, streams,
      [&](std::uint32_t, std::uint32_t, unsigned config, const Streams& indices) {
        const CaseRecords& cube = records[config];
        for (int p = 0; p < cube.polygon_count; ++p) {
          const PolygonRecord& record = cube.polygons[p];
          indices.copy_polygon(record, batch[fill]);
          counts.add(record.vertex_count);
          if (++fill == capacity) {
            counts.spill(fill - spilled_at, by_size);
            emitter.add_polygons(fill, by_size);
            fill = spilled_at = 0;
            for (std::uint64_t& count : by_size) count = 0;
            if (!emitter.flush_polygons()) return false;
          }
        }
        if (spill_between &&
            fill - spilled_at > SizeCounts::kMostBetweenSpills - CubePolygons::kMaxPolygons) {
          counts.spill(fill - spilled_at, by_size);
          spilled_at = fill;
        }
        return true;
      });
  counts.spill(fill - spilled_at, by_size);
  emitter.add_polygons(fill, by_size);
  return ok;
}

#if MVOX_HAVE_AVX2_PATH
// emit_layer_records with the running counts in AVX2 registers, compiled for AVX2: the same
// polygons in the same order.
MVOX_TARGET_AVX2 bool emit_layer_records_avx2(const EngineState& st, int lo, int hi,
                                              std::uint32_t height, Emitter& emitter) {
  EdgeStreamsAvx2 streams{EdgeStreams(st, lo, hi)};
  return emit_layer_records(st, lo, hi, height, streams, emitter);
}
#endif

// PASS 3, fast: each active cube's configuration looked up in the case table.
bool emit_layer_fast(const EngineState& st, int lo, int hi, std::uint32_t z, std::uint32_t height,
                     Emitter& emitter) {
  EdgeStreams streams(st, lo, hi);
  if (emitter.next_geometry())  // polygons by value too: the general path
    return for_each_surface_cube(
        st, lo, hi, height, streams,
        [&](std::uint32_t cx, std::uint32_t cy, unsigned config, const EdgeStreams& indices) {
          return emit_cube(cx, cy, z, config, st.table->cases[config], indices.indices(), emitter);
        });
#if MVOX_HAVE_AVX2_PATH
  if (st.use_avx2) return emit_layer_records_avx2(st, lo, hi, height, emitter);
#endif
  return emit_layer_records(st, lo, hi, height, streams, emitter);
}

// PASS 3, marching cubes: each surface cube's triangles from Lorensen and Cline's table. With
// polygons by value, each cut edge's vertex is placed once per cube (as PASS 2 placed it), with
// the sample type fixed for the whole layer.
template <int kType>
bool emit_layer_cubes_as(const EngineState& st, int lo, int hi, std::uint32_t z,
                         std::uint32_t height, Emitter& emitter) {
  const MarchingCubesTable& table = marching_cubes_table();
  const bool by_value = emitter.next_geometry() != nullptr;
  Vertex placed[cube::kEdges];  // the current cube's vertices by value, by cube edge
  EdgeStreams streams(st, lo, hi);
  return for_each_surface_cube(
      st, lo, hi, height, streams,
      [&](std::uint32_t cx, std::uint32_t cy, unsigned config, const EdgeStreams& indices) {
        const std::uint32_t* edge_index = indices.indices();
        const MarchingCubesCase& triangles = table.cases[config];
        if (by_value) {
          const float x0 = static_cast<float>(cx) - 1.0f, y0 = static_cast<float>(cy) - 1.0f;
          const float z0 = static_cast<float>(z) - 1.0f;
          for (unsigned cut = cube::cut_edges(config); cut; cut &= cut - 1) {
            const int e = lowest_set_bit(cut);
            placed[e] = cube_edge_vertex(e, x0, y0, z0, config);
            st.interpolation.place_as<kType>(placed[e]);
          }
        }
        for (int t = 0; t < triangles.triangle_count; ++t) {
          const std::uint8_t* edges = triangles.edges + 3 * t;
          Polygon& out = emitter.next_polygon();
          out.vertex_count = 3;
          for (int i = 0; i < 3; ++i) out.vertices[i] = edge_index[edges[i]];
          for (int i = 3; i < kMaxPolygonVertices; ++i) out.vertices[i] = 0;  // as emit_cube
          if (PolygonGeometry* geometry = emitter.next_geometry()) {
            geometry->vertex_count = 3;
            for (int i = 0; i < 3; ++i) geometry->vertices[i] = placed[edges[i]];
          }
          if (!emitter.commit_polygon()) return false;
        }
        return true;
      });
}

bool emit_layer_cubes(const EngineState& st, int lo, int hi, std::uint32_t z, std::uint32_t height,
                      Emitter& emitter) {
  if (const SampleType* type = st.interpolation.common_type())
    return dispatch_sample_type(*type, [&](auto tag) {
      return emit_layer_cubes_as<static_cast<int>(decltype(tag)::value)>(st, lo, hi, z, height,
                                                                         emitter);
    });
  return emit_layer_cubes_as<EdgeInterpolation::kMixedTypes>(st, lo, hi, z, height, emitter);
}

// PASS 3, literal: the merged segments of each completed cube, walked into loops.
bool emit_layer_literal(const EngineState& st, int lo, int hi, std::uint32_t z, std::uint32_t width,
                        std::uint32_t height, Emitter& emitter) {
  for (std::uint32_t cy = 0; cy <= height; ++cy) {
    for (std::uint32_t cx = 0; cx <= width; ++cx) {
      const CubeSurface& surface = st.literal.lower_cube(cx, cy);
      if (surface.segment_count == 0) continue;
      CubePolygons polygons = extract_loops(surface);
      const std::uint64_t* r0 = st.row(lo, std::int64_t{cy} - 1, height);
      const std::uint64_t* r1 = st.row(lo, cy, height);
      const std::uint64_t* r2 = st.row(hi, std::int64_t{cy} - 1, height);
      const std::uint64_t* r3 = st.row(hi, cy, height);
      const unsigned config = test_bit(r0, cx) | test_bit(r0, cx + 1) << 1 | test_bit(r1, cx) << 2 |
                              test_bit(r1, cx + 1) << 3 | test_bit(r2, cx) << 4 |
                              test_bit(r2, cx + 1) << 5 | test_bit(r3, cx) << 6 |
                              test_bit(r3, cx + 1) << 7;
      if (st.options.rule == SurfaceRule::paper_table1 && paper_table1_applies(config))
        polygons = reversed(merge_passes(~config & 0xFFu));
      std::uint32_t edge_index[cube::kEdges] = {};
      for (unsigned cut = cube::cut_edges(config); cut; cut &= cut - 1) {
        const int e = lowest_set_bit(cut);
        edge_index[e] = cube_edge_index(st, lo, hi, e, cx, cy);
      }
      if (!emit_cube(cx, cy, z, config, polygons, edge_index, emitter)) return false;
    }
  }
  return true;
}

// PASS 3 by the method and kind the options chose.
bool emit_layer_polygons(const EngineState& st, int lo, int hi, std::uint32_t z,
                         std::uint32_t width, std::uint32_t height, Emitter& emitter) {
  if (st.options.method == SurfaceMethod::cubes)
    return emit_layer_cubes(st, lo, hi, z, height, emitter);
  if (st.options.kind == EngineKind::literal)
    return emit_layer_literal(st, lo, hi, z, width, height, emitter);
  return emit_layer_fast(st, lo, hi, z, height, emitter);
}

}  // namespace

// PASSES 2 and 3 for the cube layer between slice z - 1 and slice z (slot z & 1), whose bit rows
// are in place: its vertices first, flushed, then its polygons. Slice z is the all-outer slice
// beyond the volume when `real_slice` is false: it has no x- or y-edge vertices.
Status Engine::emit_layer(detail::EngineState& st, std::uint32_t z, bool real_slice) {
  const int hi = static_cast<int>(z & 1), lo = hi ^ 1;
  Emitter emitter(st, counters_);
  const bool ok =
      emit_vertices(st, hi, z, height_, real_slice, true, &emitter, counters_.vertices) &&
      emitter.flush_vertices() && emit_layer_polygons(st, lo, hi, z, width_, height_, emitter) &&
      emitter.flush_polygons();
  return ok ? Status::ok : emitter.status();
}

Status Engine::check_slice(const SliceView& slice) const {
  const bool known_type = slice.type == SampleType::u8 || slice.type == SampleType::u16 ||
                          slice.type == SampleType::i16 || slice.type == SampleType::f32;
  if (!slice.samples || !known_type ||
      slice.row_stride_bytes < std::size_t{slice.width} * sample_bytes(slice.type))
    return Status::invalid_argument;
  if (slice.width != width_ || slice.height != height_) return Status::slice_size_mismatch;
  return Status::ok;
}

Status Engine::push_slice(const SliceView& slice) {
  if (failure_ != Status::ok) return failure_;
  if (const Status status = check_slice(slice); status != Status::ok) return status;
  if (std::uint64_t{first_slice_} + counters_.slices >= 0xFFFFFFFFu)
    return Status::invalid_argument;

  EngineState& st = *state_;
  const std::uint32_t z = next_slice();
  const int hi = static_cast<int>(z & 1), lo = hi ^ 1;
  counters_.inner_voxels +=
      classify_slice(slice, st.thresholds, st.inner[hi], st.row_words, st.occupied[hi]);
  if (st.interpolate) st.interpolation.store(hi, slice);
  if (st.options.kind == EngineKind::literal)
    st.literal.add_slice(st.inner[lo], st.inner[hi], st.row_words);

  if (const Status status = emit_layer(st, z, true); status != Status::ok) return fail(status);
  if (st.options.kind == EngineKind::literal) st.literal.advance();
  ++counters_.slices;
  return Status::ok;
}

Status Engine::finish() {
  if (failure_ != Status::ok) return failure_;
  EngineState& st = *state_;
  if (counters_.slices > 0) {
    // The layer between the last slice and the all-outer slice beyond it.
    const std::uint32_t z = next_slice();
    const int hi = static_cast<int>(z & 1);
    std::memset(st.inner[hi], 0, std::size_t{height_} * st.row_words * sizeof(std::uint64_t));
    std::memset(st.occupied[hi], 0, height_);
    st.interpolation.clear(hi);
    if (const Status status = emit_layer(st, z, false); status != Status::ok) return fail(status);
  }
  failure_ = Status::already_finished;
  return Status::ok;
}

Status Engine::begin_slab(const SliceView& previous, std::uint32_t first_slice) {
  if (failure_ != Status::ok) return failure_;
  if (first_slice == 0 || counters_.slices != 0 || first_slice_ != 0 || counters_.vertices != 0)
    return Status::invalid_argument;
  if (const Status status = check_slice(previous); status != Status::ok) return status;

  EngineState& st = *state_;
  const std::uint32_t z = first_slice - 1;
  const int hi = static_cast<int>(z & 1), lo = hi ^ 1;
  // The slot before `previous` stands for nothing: only the layer above `previous` is this
  // slab's, and nothing below it is emitted.
  std::memset(st.inner[lo], 0, std::size_t{height_} * st.row_words * sizeof(std::uint64_t));
  std::memset(st.occupied[lo], 0, height_);
  st.interpolation.clear(lo);
  // Its voxels are the previous slab's to count: classified here, not added to the counters.
  (void)classify_slice(previous, st.thresholds, st.inner[hi], st.row_words, st.occupied[hi]);
  if (st.interpolate) st.interpolation.store(hi, previous);
  if (st.options.kind == EngineKind::literal) {
    st.literal.add_slice(st.inner[lo], st.inner[hi], st.row_words);
    st.literal.advance();  // the layer below `previous` is the previous slab's
  }

  // Its x- and y-edge vertices numbered from 0 into the planes; none is made, the previous slab
  // emits them.
  (void)emit_vertices<false>(st, hi, z, height_, true, false, nullptr, 0);
  counters_.vertices = std::uint64_t{st.x_edges[hi].count} + st.y_edges[hi].count;
  counters_.shared_vertices = counters_.vertices;
  first_slice_ = first_slice;
  return Status::ok;
}

Status Engine::finish_slab() {
  if (failure_ != Status::ok) return failure_;
  failure_ = Status::already_finished;
  return Status::ok;
}

}  // namespace mvox
