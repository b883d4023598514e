#pragma once
// mvox.Mesh, what the calls that extract a whole surface return, and the options they share.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <string>

#include "mvox/engine.h"
#include "write/mesh/mesh_arrays.h"
#include "write/mesh/world_transform.h"

namespace mvox {
namespace py = pybind11;

// The engine's options for method="voxels" or "cubes" (a ValueError for any other), with
// marching voxels' vertices interpolated when asked (marching cubes' always are).
EngineOptions engine_options(const std::string& method, bool interpolate);

// spacing and origin, (x, y, z), as --spacing and --origin.
WorldTransform placement(const std::array<double, 3>& spacing, const std::array<double, 3>& origin);

// The engine's counts as a dict: slices, inner_voxels, vertices, polygons, polygons_by_size.
py::dict counters_dict(const EngineCounters& counters);

// What mvox.extract returns.
struct Mesh {
  py::array_t<float> vertices;
  py::array_t<std::int64_t> polygon_offsets;
  py::array polygon_indices;        // int32, or int64 past 2^31 vertices (MeshArrays::wide)
  py::object faces = py::none();    // (M, 3) when triangulated
  py::object normals = py::none();  // (N, 3) when asked for
  py::dict counters;
};

// Arrays from the writer's vectors; `triangles`: every face has three corners.
Mesh mesh_from(MeshArrays&& arrays, const EngineCounters& counters, bool triangles);

}  // namespace mvox
