#include "whole_volume.h"

#include <cstdint>
#include <exception>
#include <utility>

#include "mvox/workspace_buffer.h"
#include "numpy_interop.h"
#include "pipeline/aligned_arrays_sink.h"
#include "pipeline/array_extraction.h"
#include "read/memory/memory_volume_source.h"

namespace mvox {

namespace {

// The volume's geometry and type, checked as mvox.extract checks them; an array whose rows are
// not contiguous is copied when `copy` allows, else refused.
VolumeInfo volume_info(py::array& volume, bool copy) {
  if (volume.ndim() != 3)
    throw py::value_error("volume must have 3 dimensions [z, y, x] (slice, row, column), got " +
                          std::to_string(volume.ndim()));
  const SampleType type = sample_type_of(volume.dtype(), "volume");
  for (int axis = 0; axis < 3; ++axis)
    if (volume.shape(axis) <= 0 || volume.shape(axis) > 0x7fffffff)
      throw py::value_error("volume has an empty or too large axis: shape " +
                            py::str(volume.attr("shape")).cast<std::string>());
  const py::ssize_t item = volume.itemsize();
  // The engine reads each row's samples side by side; slices and rows may lie anywhere.
  const bool rows_contiguous =
      volume.strides(2) == item && volume.strides(1) >= 0 && volume.strides(0) >= 0;
  if (!rows_contiguous) {
    if (!copy)
      throw py::value_error(
          "volume's rows are not contiguous (strides " +
          py::str(volume.attr("strides")).cast<std::string>() +
          "); pass a C-contiguous array, numpy.ascontiguousarray(volume), or copy=True");
    volume = py::module_::import("numpy").attr("ascontiguousarray")(volume);
  }
  VolumeInfo info;
  info.width = static_cast<std::uint32_t>(volume.shape(2));
  info.height = static_cast<std::uint32_t>(volume.shape(1));
  info.depth = static_cast<std::uint32_t>(volume.shape(0));
  info.type = type;
  return info;
}

}  // namespace

Mesh extract(py::array volume, double threshold, std::array<double, 3> spacing,
             std::array<double, 3> origin, const std::string& method, bool triangulate,
             bool normals, bool copy, bool interpolate) {
  const VolumeInfo info = volume_info(volume, copy);
  MemoryVolumeSource source(volume.data(), info, volume.strides(0), volume.strides(1));
  ArrayExtractionOptions options;
  options.threshold = threshold;
  options.engine = engine_options(method, interpolate);
  options.placement = placement(spacing, origin);
  options.triangulate = triangulate;
  options.normals = normals;
  ArrayExtraction result;
  {
    py::gil_scoped_release release;  // the array stays alive: `volume` holds it
    result = extract_to_arrays(source, options, "mvox.extract");
  }
  return mesh_from(std::move(result.mesh), result.counters, triangulate);
}

Mesh extract_numbered_from(py::array volume, double threshold, std::uint64_t first_vertex) {
  const VolumeInfo info = volume_info(volume, false);
  MemoryVolumeSource source(volume.data(), info, volume.strides(0), volume.strides(1));
  const std::string label = "mvox._extract_numbered_from";
  const WorldTransform identity;  // the sink keeps a reference
  AlignedArraysSink sink(identity, info.depth, label, first_vertex);
  const EngineOptions options;
  WorkspaceBuffer workspace(engine_workspace_bytes(info.width, info.height, options));
  Engine engine;
  Status status = engine.init(workspace.data(), workspace.bytes(), info.width, info.height,
                              threshold, options, &sink);
  if (status == Status::ok) detail::number_vertices_from(engine, first_vertex);
  SliceView slice;
  while (status == Status::ok && source.next_slice(&slice)) status = engine.push_slice(slice);
  if (status == Status::ok) status = engine.finish();
  if (status == Status::sink_refused && sink.thrown()) std::rethrow_exception(sink.thrown());
  if (status != Status::ok)
    throw Error(label, std::string("extraction failed: ") + status_message(status));
  return mesh_from(std::move(sink.mesh()), engine.counters(), false);
}

}  // namespace mvox
