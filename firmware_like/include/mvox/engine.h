#pragma once
// The streaming surface engine: slices in, one at a time; indexed polygons out, layer by layer,
// to a PolygonSink. It runs marching voxels (the default) or classic marching cubes. All memory is
// the caller's workspace, sized by engine_workspace_bytes(); nothing is allocated after init().
//
//   const std::size_t bytes = engine_workspace_bytes(w, h, options);  // 0: refused
//   std::vector<std::uint64_t> memory(bytes / sizeof(std::uint64_t) + 1);
//   Engine engine;
//   check(engine.init(memory.data(), bytes, w, h, threshold, options, &sink));
//   for (each slice) check(engine.push_slice(slice));
//   check(engine.finish());
#include <cstddef>
#include <cstdint>

#include "mvox/polygon_sink.h"
#include "mvox/slice.h"
#include "mvox/status.h"
#include "mvox/surface_method.h"

namespace mvox {

class Engine;

namespace detail {
struct EngineState;  // pointers into the workspace, defined in engine.cpp

// For tests: makes `engine`, after init(), run the hot loops that any CPU runs instead of those
// init() chose for this CPU (AVX2 ones on x86-64 that has it), so that both are tested on one
// machine. Both give identical output.
void use_baseline_loops(Engine& engine);
// For tests: makes `engine`, after init() and before the first slice, number its vertices from
// `first` on, as if that many had come before: a volume's four billionth vertex without four
// billion vertices (polygons carry indices modulo 2^32, mvox/mesh.h). The counters count them.
void number_vertices_from(Engine& engine, std::uint64_t first);
}  // namespace detail

// Workspace pointers must be aligned to this: the engine's widest type is a 64-bit word.
// malloc and new return at least this on every platform mvox targets.
constexpr std::size_t kWorkspaceAlignment = alignof(std::uint64_t);

struct EngineOptions {
  // Marching cubes keeps the samples of the two slices of the current cube layer too, to
  // interpolate vertex positions: 8 bytes of workspace per slice pixel more (so does
  // `interpolate` below).
  SurfaceMethod method = SurfaceMethod::voxels;
  // Marching voxels only: marching cubes must keep the defaults (fast, merge_rules).
  EngineKind kind = EngineKind::fast;
  SurfaceRule rule = SurfaceRule::merge_rules;
  std::uint32_t vertices_per_batch = 4096;  // >= 1; vertex buffer size in the workspace
  std::uint32_t polygons_per_batch = 4096;  // >= 1; polygon buffer size in the workspace
  // Also send every polygon batch by value (PolygonSink::consume_polygon_geometry), for a
  // renderer. Adds polygons_per_batch * sizeof(PolygonGeometry) bytes (116 each) of workspace.
  bool polygon_geometry = false;
  // Marching voxels: move each vertex along its edge from the midpoint to where the samples,
  // interpolated linearly, cross the threshold, as marching cubes places its vertices. The
  // polygons, their indices and so the topology stay the same; a vertex between a voxel and the
  // outside of the volume keeps its midpoint, and none comes closer than 0.01 voxel to a voxel
  // centre (where a sample equals the threshold), so that every polygon can still be split into
  // triangles off the cube faces. The same workspace as marching cubes' samples.
  // Marching cubes always interpolates.
  bool interpolate = false;
};

// What the engine has seen and produced so far.
struct EngineCounters {
  std::uint64_t slices = 0;
  std::uint64_t inner_voxels = 0;
  std::uint64_t vertices = 0;
  std::uint64_t polygons = 0;
  // index = vertex count (3..7; marching cubes emits only triangles)
  std::uint64_t polygons_by_size[kMaxPolygonVertices + 1] = {};
  // An engine started by begin_slab(): the vertices of the slice before its first, numbered
  // 0 .. shared_vertices - 1 but not emitted (the previous slab emits them). `vertices` counts
  // them too, as it is the next vertex's index; the vertices emitted are the difference.
  std::uint64_t shared_vertices = 0;
};

// Bytes of workspace an engine for slices of width x height needs with these options.
// A pure function: it does not depend on the number of slices. Returns 0 when width or height
// is 0, too large to address, or the options are invalid.
std::size_t engine_workspace_bytes(std::uint32_t width, std::uint32_t height,
                                   const EngineOptions& options);

class Engine {
 public:
  Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Prepares the engine over `workspace` (borrowed; must outlive the engine and hold at least
  // engine_workspace_bytes(width, height, options) bytes aligned to kWorkspaceAlignment).
  // A voxel is inner when its sample is >= threshold; NaN samples are outer; a NaN threshold is
  // invalid_argument. `sink` is borrowed and must outlive the engine. May be called again to
  // start a new volume.
  Status init(void* workspace, std::size_t workspace_bytes, std::uint32_t width,
              std::uint32_t height, double threshold, const EngineOptions& options,
              PolygonSink* sink);

  // Classifies the next slice (z = number of slices pushed so far) and emits every vertex and
  // polygon that this slice completes. `slice.samples` is only read during the call, and need
  // not be aligned. A slice of the wrong size or type is refused and changes nothing. After
  // sink_refused the engine stays failed: every later call returns it.
  Status push_slice(const SliceView& slice);

  // Closes the volume: the layer above the last slice (outside voxels are outer) is emitted.
  Status finish();

  // Slab-parallel extraction: several engines each take a slab of consecutive slices of one
  // volume, and their outputs, joined in slab order with their vertex indices moved, are the
  // output of one engine over the whole volume.
  //
  // begin_slab(), right after init(), starts at slice `first_slice` > 0 of the volume:
  // `previous` is slice first_slice - 1, the previous slab's last. Its x- and y-edge vertices
  // are numbered 0 .. m - 1 (m = counters().shared_vertices) but not emitted, so that the
  // polygons between it and the first slice can refer to them; the slab's own vertices are
  // numbered from m on. Vertex z coordinates are the volume's slice numbers. In the joined
  // output, local index i < m is the previous slab's vertex (index of the first vertex its last
  // slice emitted) + i, and local index i >= m is (vertices before this slab) + i - m.
  Status begin_slab(const SliceView& previous, std::uint32_t first_slice);

  // Ends a slab that another slab follows: the layer above its last slice is left to the next
  // slab's engine (whose `previous` slice that is), so nothing is emitted.
  Status finish_slab();

  // The volume's slice number of the next slice push_slice() takes.
  std::uint32_t next_slice() const {
    return first_slice_ + static_cast<std::uint32_t>(counters_.slices);
  }

  const EngineCounters& counters() const { return counters_; }
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }

 private:
  friend void detail::use_baseline_loops(Engine& engine);
  friend void detail::number_vertices_from(Engine& engine, std::uint64_t first);
  Status fail(Status status);
  // invalid_argument or slice_size_mismatch for a slice this engine cannot take, else ok.
  Status check_slice(const SliceView& slice) const;
  Status emit_layer(detail::EngineState& state, std::uint32_t z, bool real_slice);

  detail::EngineState* state_ = nullptr;
  Status failure_ = Status::not_initialised;
  EngineCounters counters_;
  std::uint32_t width_ = 0;
  std::uint32_t height_ = 0;
  std::uint32_t first_slice_ = 0;  // slice number of the first slice pushed (begin_slab)
};

}  // namespace mvox
