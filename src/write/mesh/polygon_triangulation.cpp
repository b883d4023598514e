#include "write/mesh/polygon_triangulation.h"

#include <cmath>

namespace mvox {

bool on_common_cube_face(const Vertex& a, const Vertex& b) {
  const float pa[3] = {a.x, a.y, a.z};
  const float pb[3] = {b.x, b.y, b.z};
  for (int axis = 0; axis < 3; ++axis)
    if (pa[axis] == pb[axis] && std::floor(pa[axis]) == pa[axis]) return true;
  return false;
}

bool triangulate_polygon(const PolygonGeometry& polygon, PolygonTriangles* triangles) {
  *triangles = PolygonTriangles{};
  const int n = polygon.vertex_count;
  if (n < 3 || n > kMaxPolygonVertices) return false;
  const Vertex* v = polygon.vertices;
  // A fan from `apex` has the diagonals apex -> apex + 2 .. apex + n - 2. Enumerating the case
  // tables shows a fan always suffices: the only polygons with two non-neighbouring vertices on
  // one face are hexagons and heptagons that cross an ambiguous face twice, and each has two or
  // three vertices off that face to fan from (docs/surface_rules.md).
  for (int apex = 0; apex < n; ++apex) {
    bool inside_the_cube = true;
    for (int step = 2; step <= n - 2 && inside_the_cube; ++step)
      inside_the_cube = !on_common_cube_face(v[apex], v[(apex + step) % n]);
    if (!inside_the_cube) continue;
    for (int i = 1; i <= n - 2; ++i) {
      std::uint8_t* corners = triangles->corners[triangles->count++];
      corners[0] = static_cast<std::uint8_t>(apex);
      corners[1] = static_cast<std::uint8_t>((apex + i) % n);
      corners[2] = static_cast<std::uint8_t>((apex + i + 1) % n);
    }
    return true;
  }
  return false;
}

}  // namespace mvox
