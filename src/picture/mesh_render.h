#pragma once
// Rendering a mesh held in memory (a PLY file read back) with the same z-buffer renderer the
// extraction uses, so pictures of different files and methods can be compared.
#include <array>
#include <vector>

#include "mvox/zbuffer_renderer.h"
#include "read/ply/ply_reader.h"

namespace mvox {

// Smooth vertex normals for a mesh without its own: the sum of the normals of the faces around
// each vertex, each weighted by its face's area (Newell's method, so non-planar polygons work),
// normalised. Vertices on no face, or where the normals cancel, get (0, 0, 0).
std::vector<std::array<float, 3>> area_weighted_normals(const PlyMesh& mesh);

// The box around every vertex that some face uses. Returns false when there is no face.
bool face_bounds(const PlyMesh& mesh, glm::vec3* box_min, glm::vec3* box_max);

// Draws every face of `mesh` with `renderer`. `normals` (one per vertex) gives smooth shading;
// empty: flat. Faces of more than 16 vertices are drawn as the same fan, triangle by triangle.
void draw_mesh(const PlyMesh& mesh, const std::vector<std::array<float, 3>>& normals,
               ZBufferRenderer& renderer);

}  // namespace mvox
