#pragma once
// mvox.extract: the surface of a numpy volume, read in place.
#include <pybind11/numpy.h>

#include <array>
#include <cstdint>
#include <string>

#include "mesh_object.h"

namespace mvox {

Mesh extract(py::array volume, double threshold, std::array<double, 3> spacing,
             std::array<double, 3> origin, const std::string& method, bool triangulate,
             bool normals, bool copy, bool interpolate);

// For tests (mvox._extract_numbered_from): mvox.extract's common case, one engine that numbers
// vertices from `first_vertex` on, as if that many had come before, so that the arrays' indices
// pass 2^31 and 2^32 without billions of vertices. The vertices are the volume's own.
Mesh extract_numbered_from(py::array volume, double threshold, std::uint64_t first_vertex);

}  // namespace mvox
