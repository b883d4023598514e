// The Python module `mvox`: marching voxels on numpy arrays, in process.
//
//   mesh = mvox.extract(volume, threshold, spacing=(1, 1, 1), origin=(0, 0, 0),
//                       method="voxels", triangulate=False, normals=False, copy=False)
//   ex = mvox.Extractor(width, height, threshold, ...); ex.push(slice2d); ex.finish()
//
// The volume reaches the engine without a copy (read/memory/memory_volume_source.h), slice by
// slice, while the GIL is released; the mesh comes back as numpy arrays that own the vectors
// the writer filled (no copy either). The mesh is the one `mvox extract -o mesh.ply` writes for
// the same samples, vertex for vertex (pipeline/array_extraction.h).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "error.h"
#include "mvox/engine.h"
#include "mvox/workspace_buffer.h"
#include "pipeline/array_extraction.h"
#include "read/input_format.h"
#include "read/memory/memory_volume_source.h"
#include "read/raw/raw_format.h"
#include "write/mesh/mesh_arrays.h"
#include "write/mesh/mesh_format.h"

namespace py = pybind11;

namespace mvox {
namespace {

// A vector handed to numpy: the array owns it through a capsule, so nothing is copied.
template <class T>
py::array_t<T> to_numpy(ArrayOf<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new ArrayOf<T>(std::move(values));
  py::capsule owner(owned, [](void* p) { delete static_cast<ArrayOf<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), owner);
}

// Marks an object in use for the length of a call that releases the GIL, so that a second
// Python thread calling it meanwhile gets a RuntimeError instead of racing on its buffers.
// Set and cleared while holding the GIL.
class InUse {
 public:
  InUse(bool& busy, const char* what) : busy_(busy) {
    if (busy_)
      throw std::runtime_error(std::string(what) +
                               " is in use by another thread; use one object per thread");
    busy_ = true;
  }
  ~InUse() { busy_ = false; }
  InUse(const InUse&) = delete;
  InUse& operator=(const InUse&) = delete;

 private:
  bool& busy_;
};

// The sample type of a numpy dtype mvox reads, or a TypeError naming what it got.
SampleType sample_type_of(const py::dtype& dtype, const char* what) {
  // By kind, size and byte order, not by identity: a dtype that came through pickle (say, from
  // multiprocessing) is an equal but distinct object.
  const char kind = dtype.kind();
  const py::ssize_t size = dtype.itemsize();
  const char order = py::str(dtype.attr("byteorder")).cast<std::string>()[0];
  const std::uint16_t one = 1;
  const bool little_host = *reinterpret_cast<const unsigned char*>(&one) == 1;
  const bool native = order == '=' || order == '|' || order == (little_host ? '<' : '>');
  if (native && kind == 'u' && size == 1) return SampleType::u8;
  if (native && kind == 'u' && size == 2) return SampleType::u16;
  if (native && kind == 'i' && size == 2) return SampleType::i16;
  if (native && kind == 'f' && size == 4) return SampleType::f32;
  const std::string name = py::str(py::handle(dtype)).cast<std::string>();
  throw py::type_error(std::string(what) + " has dtype " + name +
                       "; mvox reads uint8, uint16, int16 and float32 (native byte order): "
                       "convert it first, e.g. volume.astype(numpy.float32)");
}

EngineOptions engine_options(const std::string& method) {
  EngineOptions options;
  if (method == "voxels") {
    options.method = SurfaceMethod::voxels;
  } else if (method == "cubes") {
    options.method = SurfaceMethod::cubes;
  } else {
    throw py::value_error("method must be \"voxels\" or \"cubes\", got \"" + method + "\"");
  }
  return options;
}

WorldTransform placement(const std::array<double, 3>& spacing,
                         const std::array<double, 3>& origin) {
  WorldTransform transform;
  for (int axis = 0; axis < 3; ++axis) {
    transform.spacing[axis] = spacing[axis];
    transform.origin[axis] = origin[axis];
  }
  return transform;
}

py::dict counters_dict(const EngineCounters& counters) {
  py::dict by_size;
  for (int size = 3; size <= kMaxPolygonVertices; ++size)
    by_size[py::int_(size)] = counters.polygons_by_size[size];
  py::dict result;
  result["slices"] = counters.slices;
  result["inner_voxels"] = counters.inner_voxels;
  result["vertices"] = counters.vertices;
  result["polygons"] = counters.polygons;
  result["polygons_by_size"] = by_size;
  return result;
}

// What mvox.extract returns.
struct Mesh {
  py::array_t<float> vertices;
  py::array_t<std::int64_t> polygon_offsets;
  py::array_t<std::int32_t> polygon_indices;
  py::object faces = py::none();    // (M, 3) when triangulated
  py::object normals = py::none();  // (N, 3) when asked for
  py::dict counters;
};

// Arrays from the writer's vectors; `triangles`: every face has three corners.
Mesh mesh_from(MeshArrays&& arrays, const EngineCounters& counters, bool triangles) {
  Mesh mesh;
  const auto vertex_count = static_cast<py::ssize_t>(arrays.vertex_count());
  const auto face_count = static_cast<py::ssize_t>(arrays.face_count());
  mesh.vertices = to_numpy(std::move(arrays.vertices), {vertex_count, 3});
  if (!arrays.normals.empty())
    mesh.normals = to_numpy(std::move(arrays.normals), {vertex_count, 3});
  if (triangles) {
    // The same indices seen as rows of three: one array shared, no copy.
    py::array_t<std::int32_t> indices =
        to_numpy(std::move(arrays.polygon_indices), {face_count * 3});
    mesh.faces = indices.attr("reshape")(face_count, 3);
    mesh.polygon_indices = indices;
  } else {
    const auto index_count = static_cast<py::ssize_t>(arrays.polygon_indices.size());
    mesh.polygon_indices = to_numpy(std::move(arrays.polygon_indices), {index_count});
  }
  mesh.polygon_offsets = to_numpy(std::move(arrays.polygon_offsets), {face_count + 1});
  mesh.counters = counters_dict(counters);
  return mesh;
}

Mesh extract(py::array volume, double threshold, std::array<double, 3> spacing,
             std::array<double, 3> origin, const std::string& method, bool triangulate,
             bool normals, bool copy) {
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
  MemoryVolumeSource source(volume.data(), info, volume.strides(0), volume.strides(1));
  ArrayExtractionOptions options;
  options.threshold = threshold;
  options.engine = engine_options(method);
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

// mvox.Extractor: slices pushed one at a time, the mesh returned as it completes. Memory: the
// engine's workspace (a function of width and height) and one layer's output, whatever the
// number of slices.
class Extractor {
 public:
  Extractor(std::uint32_t width, std::uint32_t height, double threshold,
            std::array<double, 3> spacing, std::array<double, 3> origin, const std::string& method,
            bool triangulate)
      : width_(width), height_(height), triangulate_(triangulate) {
    MeshWriterOptions mesh;
    mesh.transform = placement(spacing, origin);
    mesh.transform.check("mvox.Extractor");
    mesh.triangulate = triangulate;
    writer_ = std::make_unique<MeshArraysWriter>(mesh, "mvox.Extractor");
    EngineOptions options = engine_options(method);
    if (writer_->needs_polygon_geometry()) options.polygon_geometry = true;
    const std::size_t bytes = engine_workspace_bytes(width, height, options);
    if (bytes == 0)
      throw py::value_error("slices of " + std::to_string(width) + "x" + std::to_string(height) +
                            " are empty or too large to extract");
    workspace_ = std::make_unique<WorkspaceBuffer>(bytes);
    check(engine_.init(workspace_->data(), workspace_->bytes(), width, height, threshold, options,
                       writer_.get()));
  }

  // The vertices and faces the slice completed, with indices counted from the first slice.
  py::tuple push(py::array slice) {
    const InUse in_use(busy_, "this mvox.Extractor");
    if (finished_) throw py::value_error("push() after finish()");
    if (slice.ndim() != 2 || slice.shape(0) != height_ || slice.shape(1) != width_)
      throw py::value_error("slice must be [y, x] of shape (" + std::to_string(height_) + ", " +
                            std::to_string(width_) + "), got shape " +
                            py::str(slice.attr("shape")).cast<std::string>());
    if (slice.strides(1) != slice.itemsize() || slice.strides(0) < 0)
      throw py::value_error("slice's rows are not contiguous; pass numpy.ascontiguousarray(slice)");
    SliceView view;
    view.samples = slice.data();
    view.width = width_;
    view.height = height_;
    view.row_stride_bytes = static_cast<std::size_t>(slice.strides(0));
    view.type = sample_type_of(slice.dtype(), "slice");
    Status status;
    {
      py::gil_scoped_release release;
      status = engine_.push_slice(view);
    }
    check(status);
    return take();
  }

  py::tuple finish() {
    const InUse in_use(busy_, "this mvox.Extractor");
    if (finished_) throw py::value_error("finish() called twice");
    finished_ = true;
    check(engine_.finish());
    writer_->complete();
    return take();
  }

  py::dict counters() {
    const InUse in_use(busy_, "this mvox.Extractor");
    return counters_dict(engine_.counters());
  }

 private:
  void check(Status status) {
    if (status == Status::ok) return;
    if (status == Status::sink_refused && writer_->error()) throw *writer_->error();
    throw Error("mvox.Extractor", std::string("extraction failed: ") + status_message(status));
  }

  // What the writer holds so far, handed out and forgotten: faces' offsets count from this
  // chunk's first index, vertex indices from the volume's first vertex.
  py::tuple take() {
    MeshArrays chunk = std::move(writer_->arrays());
    writer_->arrays() = MeshArrays();
    Mesh mesh = mesh_from(std::move(chunk), engine_.counters(), triangulate_);
    return py::make_tuple(mesh.vertices, mesh.polygon_offsets, mesh.polygon_indices);
  }

  std::uint32_t width_, height_;
  bool triangulate_;
  bool finished_ = false;
  bool busy_ = false;  // a call is running (InUse)
  std::unique_ptr<MeshArraysWriter> writer_;
  std::unique_ptr<WorkspaceBuffer> workspace_;
  Engine engine_;
};

// The numpy dtype of a sample type.
py::dtype dtype_of(SampleType type) {
  switch (type) {
    case SampleType::u8: return py::dtype::of<std::uint8_t>();
    case SampleType::u16: return py::dtype::of<std::uint16_t>();
    case SampleType::i16: return py::dtype::of<std::int16_t>();
    case SampleType::f32: return py::dtype::of<float>();
  }
  return py::dtype::of<float>();
}

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

// mvox.open: the command line's readers as an iterator of slices, one pass.
class Volume {
 public:
  Volume(const py::object& paths, const std::optional<std::string>& raw)
      : input_(open_paths(input_paths(paths), raw)) {}

  const VolumeInfo& info() const { return input_.source->info(); }
  py::tuple shape() const { return py::make_tuple(info().depth, info().height, info().width); }
  py::dtype dtype() const { return dtype_of(info().type); }
  py::tuple spacing() const {
    return py::make_tuple(info().spacing[0], info().spacing[1], info().spacing[2]);
  }
  py::tuple origin() const {
    return py::make_tuple(info().origin[0], info().origin[1], info().origin[2]);
  }
  py::array_t<double> axes() const {
    py::array_t<double> axes({3, 3});
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) axes.mutable_at(a, b) = info().axes[a][b];
    return axes;
  }

  // The next slice, [y, x], copied: the reader's buffer is reused for the one after.
  py::array next() {
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

  SliceSource& source() { return *input_.source; }

 private:
  OpenedInput input_;
  bool busy_ = false;  // a call is running (InUse)
};

Mesh extract_file(const py::object& paths, double threshold, const std::optional<std::string>& raw,
                  const std::optional<std::array<double, 3>>& spacing,
                  const std::optional<std::array<double, 3>>& origin, const std::string& method,
                  bool triangulate, bool normals, unsigned threads) {
  if (threads < 1) throw py::value_error("threads must be 1 or more");
  // Listed once: `paths` may be a generator.
  const std::vector<std::string> list = input_paths(paths);
  OpenedInput input = open_paths(list, raw);
  ArrayExtractionOptions options;
  options.threshold = threshold;
  options.engine = engine_options(method);
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
// an identity placement (spacing 1, origin 0: exact in double, so the floats come out as they
// went in) and its faces as polygons, in batches; STL gets each triangle's positions.
void write_mesh(const Mesh& mesh, const std::string& path, const std::optional<std::string>& format,
                bool ascii) {
  std::optional<MeshFormat> chosen =
      format ? mesh_format_named(*format) : mesh_format_of_path(path);
  if (!chosen)
    throw py::value_error("cannot tell the mesh format of '" + path +
                          "': name it .ply, .stl or .obj, or give format=\"ply\", \"ply-ascii\", "
                          "\"stl\" or \"obj\"");
  if (ascii && *chosen == MeshFormat::ply) chosen = MeshFormat::ply_ascii;
  if (!mesh.normals.is_none())
    throw py::value_error(
        "this mesh has normals, which mvox.write does not write yet: extract it without "
        "normals=True, or use mvox extract --normals");
  // The arrays are the caller's to change: their shapes and offsets are checked before any is
  // read without bounds checks.
  if (mesh.vertices.ndim() != 2 || mesh.vertices.shape(1) != 3)
    throw py::value_error("mesh.vertices must have shape (N, 3)");
  if (mesh.polygon_offsets.ndim() != 1 || mesh.polygon_indices.ndim() != 1 ||
      mesh.polygon_offsets.shape(0) < 1)
    throw py::value_error("mesh.polygon_offsets and polygon_indices must be 1-D");
  const auto vertices = mesh.vertices.unchecked<2>();
  const auto offsets = mesh.polygon_offsets.unchecked<1>();
  const auto indices = mesh.polygon_indices.unchecked<1>();
  const py::ssize_t faces = offsets.shape(0) - 1;
  if (offsets(0) != 0 || offsets(faces) != indices.shape(0))
    throw py::value_error("mesh.polygon_offsets must run from 0 to len(polygon_indices)");
  for (py::ssize_t i = 0; i < faces; ++i) {
    const std::int64_t size = offsets(i + 1) - offsets(i);
    if (size < 3 || size > kMaxPolygonVertices)
      throw py::value_error("face " + std::to_string(i) + " has " + std::to_string(size) +
                            " vertices; the writers take 3 to 7");
    if (*chosen == MeshFormat::stl && size != 3)
      throw py::value_error("STL holds triangles only: extract with triangulate=True");
  }
  MeshWriterOptions options;
  options.comments.push_back("mvox (Python)");
  std::unique_ptr<MeshWriter> writer = open_mesh_writer(path, *chosen, options);
  auto refused = [&](Status status) {
    if (status == Status::ok) return;
    if (writer->error()) throw *writer->error();
    throw Error(path, "the writer refused the mesh");
  };
  constexpr py::ssize_t kBatch = 4096;
  std::vector<Vertex> batch;
  for (py::ssize_t first = 0; first < vertices.shape(0); first += kBatch) {
    batch.clear();
    for (py::ssize_t i = first; i < std::min(first + kBatch, vertices.shape(0)); ++i) {
      Vertex vertex;
      vertex.x = vertices(i, 0);
      vertex.y = vertices(i, 1);
      vertex.z = vertices(i, 2);
      batch.push_back(vertex);
    }
    refused(writer->consume_vertices(batch.data(), batch.size()));
  }
  std::vector<Polygon> polygons;
  std::vector<PolygonGeometry> geometry;
  for (py::ssize_t first = 0; first < faces; first += kBatch) {
    polygons.clear();
    geometry.clear();
    for (py::ssize_t i = first; i < std::min(first + kBatch, faces); ++i) {
      Polygon polygon;
      PolygonGeometry positions;
      polygon.vertex_count = positions.vertex_count =
          static_cast<std::uint8_t>(offsets(i + 1) - offsets(i));
      for (int k = 0; k < polygon.vertex_count; ++k) {
        const std::int32_t index = indices(offsets(i) + k);
        if (index < 0 || index >= vertices.shape(0))
          throw py::value_error("face " + std::to_string(i) + " refers to vertex " +
                                std::to_string(index) + " of " + std::to_string(vertices.shape(0)));
        polygon.vertices[k] = static_cast<std::uint32_t>(index);
        positions.vertices[k].x = vertices(index, 0);
        positions.vertices[k].y = vertices(index, 1);
        positions.vertices[k].z = vertices(index, 2);
      }
      polygons.push_back(polygon);
      geometry.push_back(positions);
    }
    refused(writer->consume_polygons(polygons.data(), polygons.size()));
    if (writer->needs_polygon_geometry())
      refused(writer->consume_polygon_geometry(geometry.data(), geometry.size()));
  }
  writer->finish();
}

}  // namespace
}  // namespace mvox

PYBIND11_MODULE(mvox, m) {
  using namespace mvox;
  m.doc() = "mvox: closed surfaces from volume scans by marching voxels, streamed in fixed memory";
  py::register_exception<Error>(m, "Error", PyExc_RuntimeError);

  py::class_<Mesh>(m, "Mesh", "A surface: vertices, and faces in VTK's compressed-row layout")
      .def_readonly("vertices", &Mesh::vertices, "(N, 3) float32: x, y, z of each vertex")
      .def_readonly("polygon_offsets", &Mesh::polygon_offsets,
                    "(M + 1,) int64: face i is polygon_indices[offsets[i]:offsets[i + 1]]")
      .def_readonly("polygon_indices", &Mesh::polygon_indices, "int32 vertex indices")
      .def_readonly("faces", &Mesh::faces, "(M, 3) int32 triangles, when triangulate=True")
      .def_readonly("normals", &Mesh::normals, "(N, 3) float32 unit normals, when normals=True")
      .def_readonly("counters", &Mesh::counters, "the engine's counts")
      .def("__repr__", [](const Mesh& mesh) {
        return "<mvox.Mesh: " + std::to_string(mesh.vertices.shape(0)) + " vertices, " +
               std::to_string(mesh.polygon_offsets.shape(0) - 1) + " faces>";
      });

  m.def("extract", &extract, py::arg("volume"), py::arg("threshold"),
        py::arg("spacing") = std::array<double, 3>{1, 1, 1},
        py::arg("origin") = std::array<double, 3>{0, 0, 0}, py::arg("method") = "voxels",
        py::arg("triangulate") = false, py::arg("normals") = false, py::arg("copy") = false,
        R"(The closed surface of the voxels >= threshold in `volume`, indexed [z, y, x].

volume: a numpy array of uint8, uint16, int16 or float32, read without a copy; its rows must be
    contiguous (copy=True copies an array whose rows are not).
spacing, origin: (x, y, z), as mvox extract's --spacing and --origin: vertex = origin +
    spacing * (column, row, slice).
method: "voxels" (marching voxels) or "cubes" (marching cubes).
Returns an mvox.Mesh, equal to what `mvox extract -o mesh.ply` writes for the same samples.)");

  py::class_<Extractor>(m, "Extractor",
                        "Slices pushed one at a time; each push returns the mesh it completed")
      .def(py::init<std::uint32_t, std::uint32_t, double, std::array<double, 3>,
                    std::array<double, 3>, const std::string&, bool>(),
           py::arg("width"), py::arg("height"), py::arg("threshold"),
           py::arg("spacing") = std::array<double, 3>{1, 1, 1},
           py::arg("origin") = std::array<double, 3>{0, 0, 0}, py::arg("method") = "voxels",
           py::arg("triangulate") = false)
      .def("push", &Extractor::push, py::arg("slice"),
           "Takes a [y, x] slice; returns (vertices, polygon_offsets, polygon_indices) completed "
           "by it, indices counted from the volume's first vertex")
      .def("finish", &Extractor::finish, "Ends the volume; returns the rest of the mesh")
      .def_property_readonly("counters", &Extractor::counters);

  py::class_<Volume>(m, "Volume", "A volume file or stack, read slice by slice (mvox.open)")
      .def_property_readonly("shape", &Volume::shape, "(depth, height, width)")
      .def_property_readonly("dtype", &Volume::dtype)
      .def_property_readonly("spacing", &Volume::spacing, "(x, y, z) voxel size")
      .def_property_readonly("origin", &Volume::origin, "position of voxel (0, 0, 0)")
      .def_property_readonly("axes", &Volume::axes, "rows: world directions of x, y and z")
      .def("__iter__", [](Volume& volume) -> Volume& { return volume; })
      .def("__next__", &Volume::next, "the next [y, x] slice (a copy)");

  m.def(
      "open",
      [](const py::object& paths, const std::optional<std::string>& raw) {
        return std::make_unique<Volume>(paths, raw);
      },
      py::arg("path_or_paths"), py::arg("raw") = py::none(),
      R"(Opens what `mvox extract INPUT` reads (an image stack folder or glob, TIFF, DICOM series,
NRRD, MetaImage, raw slices or a raw volume with raw="WxHxD:TYPE", as --raw), reading headers
only. Iterating gives the slices, [y, x] numpy arrays, once. Errors raise mvox.Error with the
command line's message.)");

  m.def("write", &write_mesh, py::arg("mesh"), py::arg("path"), py::arg("format") = py::none(),
        py::arg("ascii") = false,
        R"(Writes `mesh` with the command line's writers: binary PLY (ascii=True for ASCII), STL
(triangles only) or OBJ, by the path's extension or `format`; all or nothing, as mvox extract.)");

  m.def("extract_file", &extract_file, py::arg("path_or_paths"), py::arg("threshold"),
        py::arg("raw") = py::none(), py::arg("spacing") = py::none(),
        py::arg("origin") = py::none(), py::arg("method") = "voxels",
        py::arg("triangulate") = false, py::arg("normals") = false, py::arg("threads") = 1,
        R"(The surface of a file or stack, streamed slice by slice without building the volume in
Python: the mesh `mvox extract INPUT -t threshold -o mesh.ply` writes, as an mvox.Mesh, placed
by the input's own spacing, origin and axes unless spacing or origin are given.

threads: above 1, slabs of slices are read, decoded and extracted on that many threads, as
`mvox extract --threads N` does; the mesh is the same, bit for bit.)");
}
