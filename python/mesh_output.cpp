#include "mesh_output.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "error.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {

namespace {

// write_mesh() for the mesh's index type (int32, or int64 in a mesh of more than 2^31 vertices).
template <class Index>
void write_mesh_as(const Mesh& mesh, const py::array_t<Index>& index_array, const std::string& path,
                   MeshFormat chosen) {
  // The arrays are the caller's to change: their shapes and offsets are checked before any is
  // read without bounds checks.
  if (mesh.vertices.ndim() != 2 || mesh.vertices.shape(1) != 3)
    throw py::value_error("mesh.vertices must have shape (N, 3)");
  if (mesh.polygon_offsets.ndim() != 1 || mesh.polygon_indices.ndim() != 1 ||
      mesh.polygon_offsets.shape(0) < 1)
    throw py::value_error("mesh.polygon_offsets and polygon_indices must be 1-D");
  const auto vertices = mesh.vertices.unchecked<2>();
  const py::ssize_t vertex_count = vertices.shape(0);
  // Vertex normals where the format holds them; STL's face normals come from the triangles.
  const bool with_normals = !mesh.normals.is_none() && chosen != MeshFormat::stl;
  py::array_t<float> normal_array;
  if (with_normals) {
    normal_array = mesh.normals.cast<py::array_t<float>>();
    if (normal_array.ndim() != 2 || normal_array.shape(0) != vertex_count ||
        normal_array.shape(1) != 3)
      throw py::value_error("mesh.normals must have shape (N, 3), one row a vertex");
  }
  const auto offsets = mesh.polygon_offsets.unchecked<1>();
  const auto indices = index_array.template unchecked<1>();
  const py::ssize_t faces = offsets.shape(0) - 1;
  if (offsets(0) != 0 || offsets(faces) != indices.shape(0))
    throw py::value_error("mesh.polygon_offsets must run from 0 to len(polygon_indices)");
  for (py::ssize_t i = 0; i < faces; ++i) {
    const std::int64_t size = offsets(i + 1) - offsets(i);
    if (size < 3 || size > kMaxPolygonVertices)
      throw py::value_error("face " + std::to_string(i) + " has " + std::to_string(size) +
                            " vertices; the writers take 3 to 7");
    if (chosen == MeshFormat::stl && size != 3)
      throw py::value_error("STL holds triangles only: extract with triangulate=True");
  }
  MeshWriterOptions options;
  options.comments.push_back("mvox (Python)");
  options.normals_given = with_normals;
  std::unique_ptr<MeshWriter> writer = open_mesh_writer(path, chosen, options);
  auto refused = [&](Status status) {
    if (status == Status::ok) return;
    if (writer->error()) throw *writer->error();
    throw Error(path, "the writer refused the mesh");
  };
  // The vertices go in placed already: their floats are written as they are.
  constexpr py::ssize_t kBatch = 4096;
  std::vector<WorldVertex> batch;
  for (py::ssize_t first = 0; first < vertex_count; first += kBatch) {
    batch.clear();
    for (py::ssize_t i = first; i < std::min(first + kBatch, vertex_count); ++i) {
      WorldVertex vertex;
      for (int axis = 0; axis < 3; ++axis) vertex.position[axis] = vertices(i, axis);
      if (with_normals)
        for (int axis = 0; axis < 3; ++axis) vertex.normal[axis] = normal_array.at(i, axis);
      batch.push_back(vertex);
    }
    refused(writer->consume_placed_vertices(batch.data(), batch.size()));
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
        const std::int64_t index = indices(offsets(i) + k);
        if (index < 0 || index >= vertex_count)
          throw py::value_error("face " + std::to_string(i) + " refers to vertex " +
                                std::to_string(index) + " of " + std::to_string(vertex_count));
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

void write_mesh(const Mesh& mesh, const std::string& path, const std::optional<std::string>& format,
                bool ascii) {
  std::optional<MeshFormat> chosen =
      format ? mesh_format_named(*format) : mesh_format_of_path(path);
  if (!chosen)
    throw py::value_error("cannot tell the mesh format of '" + path +
                          "': name it .ply, .stl or .obj, or give format=\"ply\", \"ply-ascii\", "
                          "\"stl\" or \"obj\"");
  if (ascii && *chosen == MeshFormat::ply) chosen = MeshFormat::ply_ascii;
  // Faces are handed to the writers after every vertex, with 32-bit indices that the writers
  // make whole among the last 2^32 vertices written (mvox/mesh.h): beyond 2^32 vertices a face
  // could refer further back than that.
  if (mesh.vertices.ndim() == 2 &&
      static_cast<std::uint64_t>(mesh.vertices.shape(0)) > (std::uint64_t{1} << 32))
    throw py::value_error("mvox.write takes meshes of up to 4294967296 vertices; this one has " +
                          std::to_string(mesh.vertices.shape(0)));
  if (py::isinstance<py::array_t<std::int32_t>>(mesh.polygon_indices))
    return write_mesh_as(mesh, py::array_t<std::int32_t>(mesh.polygon_indices), path, *chosen);
  if (py::isinstance<py::array_t<std::int64_t>>(mesh.polygon_indices))
    return write_mesh_as(mesh, py::array_t<std::int64_t>(mesh.polygon_indices), path, *chosen);
  throw py::type_error("mesh.polygon_indices must be int32 or int64");
}

}  // namespace mvox
