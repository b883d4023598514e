#pragma once
// mvox.extract: the surface of a numpy volume, read in place.
#include <pybind11/numpy.h>

#include <array>
#include <string>

#include "mesh_object.h"

namespace mvox {

Mesh extract(py::array volume, double threshold, std::array<double, 3> spacing,
             std::array<double, 3> origin, const std::string& method, bool triangulate,
             bool normals, bool copy, bool interpolate);

}  // namespace mvox
