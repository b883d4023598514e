#pragma once
// Test support: a mesh read back from a file, in the form mesh_topology's checks take.
#include <array>
#include <vector>

#include "mesh_capture.h"
#include "read/ply/ply_reader.h"

namespace mvox::test {

// Vertices at these positions (axis and side left at their defaults), no polygons yet.
Mesh mesh_of_positions(const std::vector<std::array<float, 3>>& positions);

// The PLY reader's vertices and faces as a Mesh.
Mesh to_mesh(const PlyMesh& ply);

}  // namespace mvox::test
