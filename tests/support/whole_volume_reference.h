#pragma once
// Test support: the paper's method run the obvious, non-streaming way, to check the streaming
// engine against. All octant triangles of the whole volume are built first, then the x pass
// runs over the whole volume, then the y pass, then the z pass; vertices are deduplicated by
// position in a map. Slow and memory-hungry, which is the point: nothing clever to get wrong.
#include <array>
#include <vector>

#include "mesh_capture.h"

namespace mvox::test {

Mesh whole_volume_reference(const BinaryVolume& volume);

// A mesh as numbering-free geometry: each polygon as its vertex positions, rotated to start at
// the smallest position (orientation kept), the polygons sorted. Two meshes with the same
// surface give equal canonical forms whatever order their vertices and polygons came in.
using CanonicalPolygon = std::vector<std::array<float, 3>>;
std::vector<CanonicalPolygon> canonical_form(const Mesh& mesh);

}  // namespace mvox::test
