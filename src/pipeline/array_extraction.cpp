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
#include "pipeline/aligned_arrays_sink.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_extraction.h"

namespace mvox {

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
