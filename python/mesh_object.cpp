#include "mesh_object.h"

#include <utility>

#include "numpy_interop.h"

namespace mvox {

EngineOptions engine_options(const std::string& method, bool interpolate) {
  EngineOptions options;
  options.interpolate = interpolate;
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

Mesh mesh_from(MeshArrays&& arrays, const EngineCounters& counters, bool triangles) {
  Mesh mesh;
  const auto vertex_count = static_cast<py::ssize_t>(arrays.vertex_count());
  const auto face_count = static_cast<py::ssize_t>(arrays.face_count());
  mesh.vertices = to_numpy(std::move(arrays.vertices), {vertex_count, 3});
  if (!arrays.normals.empty())
    mesh.normals = to_numpy(std::move(arrays.normals), {vertex_count, 3});
  // The indices as numpy owns them: int32, or int64 for a mesh past 2^31 vertices.
  const auto index_count = static_cast<py::ssize_t>(arrays.index_count());
  py::array indices =
      arrays.wide ? py::array(to_numpy(std::move(arrays.wide_polygon_indices), {index_count}))
                  : py::array(to_numpy(std::move(arrays.polygon_indices), {index_count}));
  // Triangles: the same indices seen as rows of three, one array shared, no copy.
  if (triangles) mesh.faces = indices.attr("reshape")(face_count, 3);
  mesh.polygon_indices = indices;
  mesh.polygon_offsets = to_numpy(std::move(arrays.polygon_offsets), {face_count + 1});
  mesh.counters = counters_dict(counters);
  return mesh;
}

}  // namespace mvox
