#include "pipeline/array_extraction.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <utility>

#include "error.h"
#include "picture/normal_window.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_extraction.h"

namespace mvox {
namespace {

// The common case, in a sink of its own: axis-aligned placement that does not mirror, polygons as
// the engine makes them, no normals. Then MeshWriter's work reduces to origin + spacing * v per
// vertex (the very expression of WorldTransform::axis_aligned_position, rounded to float as the
// writers round it) and a copy of each polygon, and its batch copies and per-batch checks, which
// cost as much as extraction itself here, are left out: the engine's output is trusted as the
// core's tests check it.
class AlignedArraysSink : public PolygonSink {
 public:
  AlignedArraysSink(const WorldTransform& placement, std::uint32_t depth, const std::string& label)
      : placement_(placement), depth_(depth), label_(label) {
    identity_ = true;
    for (int axis = 0; axis < 3; ++axis)
      identity_ = identity_ && placement.spacing[axis] == 1.0 && placement.origin[axis] == 0.0;
  }

  // The engine is built without exceptions: nothing may leave these calls. A failure is kept
  // and the engine told to stop; extract_to_arrays rethrows it.
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    try {
      return take_vertices(vertices, vertex_count);
    } catch (...) {
      thrown_ = std::current_exception();
      return Status::sink_refused;
    }
  }

  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    try {
      return take_polygons(polygons, polygon_count);
    } catch (...) {
      thrown_ = std::current_exception();
      return Status::sink_refused;
    }
  }

  MeshArrays& mesh() { return mesh_; }
  const std::optional<Error>& error() const { return error_; }
  std::exception_ptr thrown() const { return thrown_; }

  // Gives back what the predictions reserved beyond the mesh, when that is much.
  void trim() {
    auto fit = [](auto& array) {
      if (array.capacity() > 2 * array.size() + (std::size_t{1} << 20)) array.shrink_to_fit();
    };
    fit(mesh_.vertices);
    fit(mesh_.polygon_offsets);
    fit(mesh_.polygon_indices);
  }

 private:
  Status take_vertices(const Vertex* vertices, std::size_t vertex_count) {
    const std::size_t first = mesh_.vertices.size();
    // The share of the volume done so far, from the last vertex's slice (vertices come slice
    // by slice): the arrays are grown once or twice to the size it predicts, rather than
    // doubled a dozen times, each time copying what they hold.
    if (vertex_count > 0)
      done_ = std::min(1.0, (vertices[vertex_count - 1].z + 1.0) / (depth_ + 1.0));
    // One float of room past the batch: append_vertex_positions copies vertices whole.
    grow(mesh_.vertices, first + 3 * vertex_count + 1);
    if (identity_) {
      // Spacing 1 and origin 0: 0 + 1 * v in double is v exactly, so the float is v itself.
      append_vertex_positions(mesh_, vertices, vertex_count);
      return Status::ok;
    }
    mesh_.vertices.resize(first + 3 * vertex_count);
    float* out = mesh_.vertices.data() + first;
    for (std::size_t i = 0; i < vertex_count; ++i, out += 3) {
      const Vector3d world =
          placement_.axis_aligned_position(vertices[i].x, vertices[i].y, vertices[i].z);
      for (int axis = 0; axis < 3; ++axis) {
        // Converting a double beyond float's range is undefined behaviour: refuse as the
        // writers do.
        if (!(std::fabs(world[axis]) <= std::numeric_limits<float>::max())) {
          error_ = Error(label_, "vertex " + std::to_string(first / 3 + i) +
                                     " lies outside the float range after spacing and origin");
          return Status::sink_refused;
        }
        out[axis] = static_cast<float>(world[axis]);
      }
    }
    return Status::ok;
  }

  Status take_polygons(const Polygon* polygons, std::size_t polygon_count) {
    // Room for seven indices a polygon, append_polygons' slack: the prediction is made from
    // the indices held, so the slack inflates it by one batch at most.
    grow(mesh_.polygon_indices, mesh_.polygon_indices.size() + polygon_count * kMaxPolygonVertices);
    grow(mesh_.polygon_offsets, mesh_.polygon_offsets.size() + polygon_count);
    append_polygons(mesh_, polygons, polygon_count);
    return Status::ok;
  }

  // Room for `needed` numbers: doubling until a tenth of the volume is done, then what the share
  // done predicts for the whole volume, with a margin, and at most 8 times what is held: a
  // surface in the first slices of a deep volume must not reserve gigabytes.
  template <class Array>
  void grow(Array& array, std::size_t needed) {
    if (needed <= array.capacity()) return;
    if (done_ < 0.1) {
      array.reserve(2 * needed);
      return;
    }
    // Predicted afresh at every growth, so that an early underestimate costs one more copy, not
    // doubling after doubling.
    const double predicted = 1.1 * static_cast<double>(needed) / done_;
    const double capped = std::min(predicted, 8.0 * static_cast<double>(needed));
    array.reserve(std::max<std::size_t>(needed + needed / 8, static_cast<std::size_t>(capped)));
  }

  const WorldTransform& placement_;
  std::uint32_t depth_;
  bool identity_ = false;  // spacing 1, origin 0
  double done_ = 0;        // of the volume, by the last vertex's slice
  const std::string& label_;
  MeshArrays mesh_;
  std::optional<Error> error_;
  std::exception_ptr thrown_;
};

}  // namespace

ArrayExtraction extract_to_arrays(SliceSource& source, const ArrayExtractionOptions& options,
                                  const std::string& label) {
  const VolumeInfo& volume = source.info();
  // The placement is checked as the command line checks --spacing and --origin, naming `label`.
  options.placement.check(label);
  std::optional<NormalWindow> window;
  const std::array<double, 3> spacing = {options.placement.spacing[0], options.placement.spacing[1],
                                         options.placement.spacing[2]};
  // Slabs when asked and the volume has two or more.
  const bool slabs = options.threads > 1 && slab_count(volume, 0) >= 2;
  if (!slabs && !options.normals && !options.triangulate && options.placement.is_axis_aligned() &&
      !options.placement.mirrors()) {
    AlignedArraysSink sink(options.placement, volume.depth, label);
    const PipelineResult result =
        run_pipeline(source, options.threshold, options.engine, sink, label);
    if (result.status == Status::sink_refused && sink.thrown())
      std::rethrow_exception(sink.thrown());  // std::bad_alloc stays itself: MemoryError
    if (result.status == Status::sink_refused && sink.error()) throw *sink.error();
    if (result.status != Status::ok)
      throw Error(label, std::string("extraction failed: ") + status_message(result.status));
    sink.trim();
    return ArrayExtraction{std::move(sink.mesh()), result.counters};
  }
  if (options.normals && !slabs) window.emplace(volume, spacing, label);
  MeshWriterOptions mesh;
  mesh.transform = options.placement;
  mesh.triangulate = options.triangulate;
  mesh.normals = window ? &window->normals() : nullptr;
  mesh.normals_given = options.normals && slabs;  // each slab computes its own
  MeshArraysWriter writer(mesh, label);
  EngineOptions engine = options.engine;
  if (writer.needs_polygon_geometry()) engine.polygon_geometry = true;

  PipelineResult result;
  if (slabs) {
    SlabOptions slab_options;
    slab_options.threads = options.threads;
    slab_options.normals = options.normals;
    slab_options.spacing = spacing;
    result = run_slab_pipeline(source, options.threshold, engine, &writer, slab_options, label);
  } else {
    PipelineSinks sinks;
    sinks.mesh = &writer;
    if (window) sinks.window = &window->window();
    result = run_pipeline(source, options.threshold, engine, sinks, label);
  }
  if (result.status == Status::sink_refused && writer.error()) throw *writer.error();
  if (result.status != Status::ok)
    throw Error(label, std::string("extraction failed: ") + status_message(result.status));
  writer.complete();
  return ArrayExtraction{std::move(writer.arrays()), result.counters};
}

}  // namespace mvox
