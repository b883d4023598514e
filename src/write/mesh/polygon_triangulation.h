#pragma once
// Splitting the engine's polygons into triangles for --triangulate and STL, never into a
// triangle that lies in a cube face (docs/design.md section 4; docs/surface_rules.md, "Triangles").
//
// Every marching-voxels vertex is the midpoint of a cube edge, so it has two integer voxel
// coordinates: it lies on two cube faces, the planes x = c, y = c or z = c (c an integer) that
// hold its edge. Every polygon edge lies on a face of the polygon's cube. A diagonal whose two
// ends lie on one cube face runs across that face: a triangle on it may lie in the face, and the
// neighbouring cube, which sees the same face, may put its own diagonal there too, so that three
// or four triangles meet at one edge. A diagonal between vertices with no face in common runs
// through the inside of the cube, where no other cube's triangles are.
#include <cstdint>

#include "mvox/mesh.h"

namespace mvox {

constexpr int kMaxPolygonTriangles = kMaxPolygonVertices - 2;

// True when `a` and `b` (voxel units) both lie on one plane x = c, y = c or z = c with c an
// integer: a coordinate they share that is a whole number.
bool on_common_cube_face(const Vertex& a, const Vertex& b);

// The triangles of one polygon, as positions in its vertex list (0 .. vertex_count - 1), each
// wound as the polygon is.
struct PolygonTriangles {
  int count = 0;
  std::uint8_t corners[kMaxPolygonTriangles][3] = {};
};

// The vertex that `polygon` (3 to 7 vertices in voxel units) is fanned from: the first whose
// diagonals all avoid on_common_cube_face(); 0 for a triangle, which has none. -1 when no fan
// avoids the faces or the vertex count is out of range. Its triangles are then
// (apex, apex + i, apex + i + 1), i = 1 .. vertex_count - 2, positions modulo vertex_count.
int fan_apex(const PolygonGeometry& polygon);

// Splits `polygon` (3 to 7 vertices in voxel units, before any world transform) into
// vertex_count - 2 triangles: the fan from the first vertex whose diagonals all avoid
// on_common_cube_face(), so no triangle lies in a cube face. A triangle is returned as it is.
// Returns false, leaving `triangles` empty, when no fan avoids the faces (never for a polygon
// of either surface rule: polygon_triangulation_test checks all 256 configurations of both) or
// the vertex count is out of range.
bool triangulate_polygon(const PolygonGeometry& polygon, PolygonTriangles* triangles);

}  // namespace mvox
