// The Python module `mvox`: marching voxels on numpy arrays, in process. This file only binds
// the calls to Python; each lives in a file of its own:
//
//   mesh = mvox.extract(volume, threshold, ...)      whole_volume.h: a numpy volume, in place
//   ex = mvox.Extractor(width, height, threshold, ...); ex.push(slice2d); ex.finish()
//                                                    slice_stream.h: slices one at a time
//   mvox.open(path), mvox.extract_file(path, ...)    volume_files.h: the command line's readers
//   mvox.write(mesh, path)                           mesh_output.h: its writers
//
// Volumes reach the engine without a copy, while the GIL is released; meshes come back as numpy
// arrays that own the memory the writer filled (numpy_interop.h, mesh_object.h), equal vertex for
// vertex to what `mvox extract -o mesh.ply` writes for the same samples.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "error.h"
#include "mesh_object.h"
#include "mesh_output.h"
#include "slice_stream.h"
#include "volume_files.h"
#include "whole_volume.h"

namespace py = pybind11;

PYBIND11_MODULE(mvox, m) {
  using namespace mvox;
  m.doc() = "mvox: closed surfaces from volume scans by marching voxels, streamed in fixed memory";
  py::register_exception<Error>(m, "Error", PyExc_RuntimeError);

  py::class_<Mesh>(m, "Mesh", "A surface: vertices, and faces in VTK's compressed-row layout")
      .def_readonly("vertices", &Mesh::vertices, "(N, 3) float32: x, y, z of each vertex")
      .def_readonly("polygon_offsets", &Mesh::polygon_offsets,
                    "(M + 1,) int64: face i is polygon_indices[offsets[i]:offsets[i + 1]]")
      .def_readonly("polygon_indices", &Mesh::polygon_indices,
                    "int32 vertex indices (int64 in a mesh of more than 2^31 vertices)")
      .def_readonly("faces", &Mesh::faces,
                    "(M, 3) triangles, when triangulate=True: polygon_indices' memory")
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
        py::arg("interpolate") = false,
        R"(The closed surface of the voxels >= threshold in `volume`, indexed [z, y, x].

volume: a numpy array of uint8, uint16, int16 or float32, read without a copy; its rows must be
    contiguous (copy=True copies an array whose rows are not).
spacing, origin: (x, y, z), as mvox extract's --spacing and --origin: vertex = origin +
    spacing * (column, row, slice).
method: "voxels" (marching voxels) or "cubes" (marching cubes).
interpolate: marching voxels' vertices moved along their edges from the midpoints to where the
    interpolated samples cross the threshold, as marching cubes places them: the same polygons,
    a smooth surface.
Returns an mvox.Mesh, equal to what `mvox extract -o mesh.ply` writes for the same samples.)");

  py::class_<Extractor>(m, "Extractor",
                        "Slices pushed one at a time; each push returns the mesh it completed")
      .def(py::init<std::uint32_t, std::uint32_t, double, std::array<double, 3>,
                    std::array<double, 3>, const std::string&, bool, bool, bool>(),
           py::arg("width"), py::arg("height"), py::arg("threshold"),
           py::arg("spacing") = std::array<double, 3>{1, 1, 1},
           py::arg("origin") = std::array<double, 3>{0, 0, 0}, py::arg("method") = "voxels",
           py::arg("triangulate") = false, py::arg("normals") = false,
           py::arg("interpolate") = false)
      .def("push", &Extractor::push, py::arg("slice"),
           "Takes a [y, x] slice; returns (vertices, polygon_offsets, polygon_indices) completed "
           "by it, indices counted from the volume's first vertex (int32; int64 once the volume "
           "has passed 2^31 vertices), and with normals=True the "
           "vertices' normals fourth (the mesh then comes one slice later: a normal needs the "
           "slices on both sides)")
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
(triangles only) or OBJ, by the path's extension or `format`; all or nothing, as mvox extract.
A mesh with normals has them written to PLY and OBJ; STL holds face normals only. Meshes of up to
2^32 vertices.)");

  m.def("_extract_numbered_from", &extract_numbered_from, py::arg("volume"), py::arg("threshold"),
        py::arg("first_vertex"),
        "For tests: mvox.extract(volume, threshold) with the vertices numbered from "
        "first_vertex, so that indices pass 2^31 and 2^32 without billions of vertices");

  m.def("extract_file", &extract_file, py::arg("path_or_paths"), py::arg("threshold"),
        py::arg("raw") = py::none(), py::arg("spacing") = py::none(),
        py::arg("origin") = py::none(), py::arg("method") = "voxels",
        py::arg("triangulate") = false, py::arg("normals") = false, py::arg("threads") = 1,
        py::arg("interpolate") = false,
        R"(The surface of a file or stack, streamed slice by slice without building the volume in
Python: the mesh `mvox extract INPUT -t threshold -o mesh.ply` writes, as an mvox.Mesh, placed
by the input's own spacing, origin and axes unless spacing or origin are given.

threads: above 1, slabs of slices are read, decoded and extracted on that many threads, as
`mvox extract --threads N` does; the mesh is the same, bit for bit.)");
}
