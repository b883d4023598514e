#include "pipeline/array_extraction.h"

#include <array>
#include <optional>
#include <utility>

#include "error.h"
#include "picture/normal_window.h"
#include "pipeline/pipeline.h"

namespace mvox {

ArrayExtraction extract_to_arrays(SliceSource& source, const ArrayExtractionOptions& options,
                                  const std::string& label) {
  const VolumeInfo& volume = source.info();
  // The placement is checked as the command line checks --spacing and --origin, naming `label`.
  options.placement.check(label);
  std::optional<NormalWindow> window;
  const std::array<double, 3> spacing = {options.placement.spacing[0], options.placement.spacing[1],
                                         options.placement.spacing[2]};
  if (options.normals) window.emplace(volume, spacing, label);
  MeshWriterOptions mesh;
  mesh.transform = options.placement;
  mesh.triangulate = options.triangulate;
  mesh.normals = window ? &window->normals() : nullptr;
  MeshArraysWriter writer(mesh, label);
  EngineOptions engine = options.engine;
  if (writer.needs_polygon_geometry()) engine.polygon_geometry = true;

  PipelineSinks sinks;
  sinks.mesh = &writer;
  if (window) sinks.window = &window->window();
  const PipelineResult result = run_pipeline(source, options.threshold, engine, sinks, label);
  if (result.status == Status::sink_refused && writer.error()) throw *writer.error();
  if (result.status != Status::ok)
    throw Error(label, std::string("extraction failed: ") + status_message(result.status));
  writer.complete();
  return ArrayExtraction{std::move(writer.arrays()), result.counters};
}

}  // namespace mvox
