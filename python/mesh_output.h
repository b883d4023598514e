#pragma once
// mvox.write: a Mesh through the command line's writers.
#include <optional>
#include <string>

#include "mesh_object.h"

namespace mvox {

// Binary PLY (`ascii` for ASCII), STL (triangles only) or OBJ, by the path's extension or
// `format`; all or nothing, as mvox extract writes. The mesh's normals, when it has them, go
// where the format has room for vertex normals (PLY, OBJ); STL has face normals only.
void write_mesh(const Mesh& mesh, const std::string& path, const std::optional<std::string>& format,
                bool ascii);

}  // namespace mvox
