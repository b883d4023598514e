#include "slice_stream.h"

#include <utility>

#include "error.h"
#include "mesh_object.h"
#include "numpy_interop.h"

namespace mvox {

Extractor::Extractor(std::uint32_t width, std::uint32_t height, double threshold,
                     std::array<double, 3> spacing, std::array<double, 3> origin,
                     const std::string& method, bool triangulate, bool normals, bool interpolate)
    : width_(width), height_(height), triangulate_(triangulate) {
  MeshWriterOptions mesh;
  mesh.transform = placement(spacing, origin);
  mesh.transform.check("mvox.Extractor");
  mesh.triangulate = triangulate;
  if (normals) {
    // Made for the widest samples; restart_for() narrows it to the first slice's type.
    VolumeInfo slices;
    slices.width = width;
    slices.height = height;
    slices.type = SampleType::f32;
    normals_ = std::make_unique<NormalWindow>(slices, spacing, "mvox.Extractor");
    mesh.normals = &normals_->normals();
  }
  writer_ = std::make_unique<MeshArraysWriter>(mesh, "mvox.Extractor");
  EngineOptions options = engine_options(method, interpolate);
  if (writer_->needs_polygon_geometry()) options.polygon_geometry = true;
  const std::size_t bytes = engine_workspace_bytes(width, height, options);
  if (bytes == 0)
    throw py::value_error("slices of " + std::to_string(width) + "x" + std::to_string(height) +
                          " are empty or too large to extract");
  workspace_ = std::make_unique<WorkspaceBuffer>(bytes);
  check(engine_.init(workspace_->data(), workspace_->bytes(), width, height, threshold, options,
                     writer_.get()));
}

py::tuple Extractor::push(py::array slice) {
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
  if (normals_ && type_ && *type_ != view.type)
    throw py::type_error(
        "slice has dtype " + py::str(py::handle(slice.dtype())).cast<std::string>() +
        " and the first slice " + py::str(py::handle(dtype_of(*type_))).cast<std::string>() +
        "; with normals=True every slice must have the first one's dtype");
  if (normals_ && !type_) normals_->restart_for(view.type);
  type_ = view.type;
  Status status;
  {
    py::gil_scoped_release release;
    status = take(view);
  }
  check(status);
  return piece();
}

Status Extractor::take(const SliceView& slice) {
  if (!normals_) return engine_.push_slice(slice);
  SliceWindow& window = normals_->window();
  if (const Status status = window.push(slice); status != Status::ok) return status;
  // The engine takes the slice before the newest: the window then holds both its neighbours.
  if (window.slices() < 2) return Status::ok;
  return engine_.push_slice(window.slice(window.slices() - 2));
}

py::tuple Extractor::finish() {
  const InUse in_use(busy_, "this mvox.Extractor");
  if (finished_) throw py::value_error("finish() called twice");
  finished_ = true;
  if (normals_ && normals_->window().slices() >= 1) {
    const SliceWindow& window = normals_->window();
    check(engine_.push_slice(window.slice(window.slices() - 1)));
  }
  check(engine_.finish());
  writer_->complete();
  return piece();
}

py::dict Extractor::counters() {
  const InUse in_use(busy_, "this mvox.Extractor");
  return counters_dict(engine_.counters());
}

void Extractor::check(Status status) {
  if (status == Status::ok) return;
  if (status == Status::sink_refused && writer_->error()) throw *writer_->error();
  throw Error("mvox.Extractor", std::string("extraction failed: ") + status_message(status));
}

py::tuple Extractor::piece() {
  MeshArrays chunk = std::move(writer_->arrays());
  writer_->arrays() = MeshArrays();
  Mesh mesh = mesh_from(std::move(chunk), engine_.counters(), triangulate_);
  if (!normals_) return py::make_tuple(mesh.vertices, mesh.polygon_offsets, mesh.polygon_indices);
  // A piece without vertices still has a (0, 3) array of normals, as it has of vertices.
  py::object normals = mesh.normals.is_none()
                           ? py::object(py::array_t<float>(std::vector<py::ssize_t>{0, 3}))
                           : mesh.normals;
  return py::make_tuple(mesh.vertices, mesh.polygon_offsets, mesh.polygon_indices, normals);
}

}  // namespace mvox
