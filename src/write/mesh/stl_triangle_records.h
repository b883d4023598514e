#pragma once
// Binary STL's triangle records, made straight from the engine's polygons: a polygon's corners
// placed in the world once (corner_placement.h), the polygon split into the fan that avoids cube
// faces (polygon_triangulation.h), and each triangle's record written from the placed corners,
// its normal filled in afterwards, two triangles at a time. No face list or per-triangle copy of
// positions lies between the engine's geometry and the file's buffer: at 1024^3 (17 million
// triangles) those copies took longer than the records.
#include <cstddef>

#include "mvox/mesh.h"
#include "write/mesh/corner_placement.h"

namespace mvox {

// Binary STL: a triangle is its normal and three vertices as floats, and a 16-bit attribute.
constexpr std::size_t kStlTriangleBytes = 50;
// A polygon of kMaxPolygonVertices corners is split into that many less two triangles.
constexpr std::size_t kMostStlBytesPerPolygon = (kMaxPolygonVertices - 2) * kStlTriangleBytes;
// Bytes past its last record that make_stl_triangle_records() may write: each corner goes out as
// 16 bytes, the last one's fourth float over the attribute and two bytes beyond.
constexpr std::size_t kStlRecordSlack = 2;

struct StlRecordsMade {
  std::size_t polygons = 0;
  std::size_t triangles = 0;
};

// The records of the triangles of `count` polygons, one after the other into `out`, which must
// have room for count * kMostStlBytesPerPolygon + kStlRecordSlack bytes. A polygon's triangles
// are those of triangulate_polygon() (a triangle is itself), each with its corners in that
// order, or walked backwards from the first when `mirrors` (a mirroring placement turns
// counter-clockwise into clockwise); its vertices are `placement`'s floats, its normal
// stl_face_normal() of them, its attribute 0. Stops before the first polygon it cannot make:
// one with a corner beyond float's range, one that no fan splits, or one of fewer than 3 or more
// than kMaxPolygonVertices corners. The caller names that polygon's problem.
StlRecordsMade make_stl_triangle_records(const CornerPlacement& placement, bool mirrors,
                                         const PolygonGeometry* polygons, std::size_t count,
                                         unsigned char* out);

// The unit normal of the triangle as written (float vertices, computed in double), by the
// right-hand rule; zero when the rounded vertices have no area.
void stl_face_normal(const float (*p)[3], float normal[3]);

#if defined(__SSE2__)
// stl_face_normal() of two triangles at once, one in each lane of SSE2's doubles: the same
// operations in the same order, so the same floats. The square root and the three divisions,
// whose latency bounds the scalar version, are then shared by the pair.
void stl_face_normals(const float (*p)[3], const float (*q)[3], float normal_p[3],
                      float normal_q[3]);
#endif

}  // namespace mvox
