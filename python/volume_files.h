#pragma once
// mvox.open and mvox.extract_file: the command line's readers from Python.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <optional>
#include <string>

#include "mesh_object.h"
#include "read/input_format.h"

namespace mvox {
namespace py = pybind11;

// mvox.open: the command line's readers as an iterator of slices, one pass.
class Volume {
 public:
  Volume(const py::object& paths, const std::optional<std::string>& raw);

  const VolumeInfo& info() const { return input_.source->info(); }
  py::tuple shape() const { return py::make_tuple(info().depth, info().height, info().width); }
  py::dtype dtype() const;
  py::tuple spacing() const;
  py::tuple origin() const;
  py::array_t<double> axes() const;

  // The next slice, [y, x], copied: the reader's buffer is reused for the one after.
  py::array next();

 private:
  OpenedInput input_;
  bool busy_ = false;  // a call is running (InUse)
};

// mvox.extract_file: the surface of a file or stack, streamed slice by slice.
Mesh extract_file(const py::object& paths, double threshold, const std::optional<std::string>& raw,
                  const std::optional<std::array<double, 3>>& spacing,
                  const std::optional<std::array<double, 3>>& origin, const std::string& method,
                  bool triangulate, bool normals, unsigned threads, bool interpolate);

}  // namespace mvox
