#include "volume_files.h"

#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "numpy_interop.h"
#include "pipeline/array_extraction.h"
#include "read/raw/raw_format.h"

namespace mvox {

namespace {

// INPUT as the command line takes it: one path, or several (slice files).
std::vector<std::string> input_paths(const py::object& paths) {
  if (py::isinstance<py::str>(paths) || py::hasattr(paths, "__fspath__"))
    return {py::str(py::module_::import("os").attr("fspath")(paths)).cast<std::string>()};
  std::vector<std::string> list;
  for (const py::handle item : paths)
    list.push_back(py::str(py::module_::import("os").attr("fspath")(item)).cast<std::string>());
  if (list.empty()) throw py::value_error("no input paths");
  return list;
}

OpenedInput open_paths(const std::vector<std::string>& paths,
                       const std::optional<std::string>& raw) {
  InputOptions options;
  if (raw) options.raw = parse_raw_format(*raw);
  return open_input(paths, options);
}

}  // namespace

Volume::Volume(const py::object& paths, const std::optional<std::string>& raw)
    : input_(open_paths(input_paths(paths), raw)) {}

py::dtype Volume::dtype() const { return dtype_of(info().type); }

py::tuple Volume::spacing() const {
  return py::make_tuple(info().spacing[0], info().spacing[1], info().spacing[2]);
}

py::tuple Volume::origin() const {
  return py::make_tuple(info().origin[0], info().origin[1], info().origin[2]);
}

py::array_t<double> Volume::axes() const {
  py::array_t<double> axes({3, 3});
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) axes.mutable_at(a, b) = info().axes[a][b];
  return axes;
}

py::array Volume::next() {
  const InUse in_use(busy_, "this mvox.Volume");
  SliceView slice;
  bool more = false;
  {
    py::gil_scoped_release release;
    more = input_.source->next_slice(&slice);
  }
  if (!more) throw py::stop_iteration();
  py::array out(dtype_of(slice.type),
                {static_cast<py::ssize_t>(slice.height), static_cast<py::ssize_t>(slice.width)});
  const std::size_t row_bytes = std::size_t{slice.width} * sample_bytes(slice.type);
  auto* target = static_cast<unsigned char*>(out.mutable_data());
  for (std::uint32_t y = 0; y < slice.height; ++y)
    std::memcpy(target + y * row_bytes,
                static_cast<const unsigned char*>(slice.samples) + y * slice.row_stride_bytes,
                row_bytes);
  return out;
}

Mesh extract_file(const py::object& paths, double threshold, const std::optional<std::string>& raw,
                  const std::optional<std::array<double, 3>>& spacing,
                  const std::optional<std::array<double, 3>>& origin, const std::string& method,
                  bool triangulate, bool normals, unsigned threads, bool interpolate) {
  if (threads < 1) throw py::value_error("threads must be 1 or more");
  // Listed once: `paths` may be a generator.
  const std::vector<std::string> list = input_paths(paths);
  OpenedInput input = open_paths(list, raw);
  ArrayExtractionOptions options;
  options.threshold = threshold;
  options.engine = engine_options(method, interpolate);
  // The input's own placement (DICOM orientation, NRRD space directions...), as the command
  // line places it; spacing and origin, when given, win as --spacing and --origin do.
  options.placement = WorldTransform::of_volume(input.source->info());
  for (int axis = 0; axis < 3; ++axis) {
    if (spacing) options.placement.spacing[axis] = (*spacing)[axis];
    if (origin) options.placement.origin[axis] = (*origin)[axis];
  }
  options.triangulate = triangulate;
  options.normals = normals;
  options.threads = threads;
  const std::string label = list.size() == 1 ? list.front() : list.front() + " ...";
  ArrayExtraction result;
  {
    py::gil_scoped_release release;
    result = extract_to_arrays(*input.source, options, label);
  }
  return mesh_from(std::move(result.mesh), result.counters, triangulate);
}

// mvox.write: a Mesh through the command line's writers. Its world vertices go in as vertices of

}  // namespace mvox
