#include "write/mesh/polygon_triangulation.h"

#include <cmath>
#include <cstdint>

namespace mvox {
namespace {

// floor(value) == value, without floor: below 2^23 a float is whole when truncating it to an
// integer loses nothing; from 2^23 on every float is whole, infinities too (floor(inf) is inf),
// and NaN never is. floorf is a library call on SSE2, and the writer asks for every vertex of
// every polygon it splits.
bool is_whole(float value) {
  if (!(std::fabs(value) < 8388608.0f)) return value == value;
  return static_cast<float>(static_cast<std::int32_t>(value)) == value;
}

// A coordinate that `a` and `b` share and that is a whole number: the plane of a cube face
// that holds both. The cheap comparison first: most pairs share no coordinate at all.
inline bool share_a_cube_face(const Vertex& a, const Vertex& b) {
  return (a.x == b.x && is_whole(a.x)) || (a.y == b.y && is_whole(a.y)) ||
         (a.z == b.z && is_whole(a.z));
}

}  // namespace

bool on_common_cube_face(const Vertex& a, const Vertex& b) { return share_a_cube_face(a, b); }

int fan_apex(const PolygonGeometry& polygon) {
  const int n = polygon.vertex_count;
  if (n < 3 || n > kMaxPolygonVertices) return -1;
  if (n == 3) return 0;
  const Vertex* v = polygon.vertices;
  // A fan from `apex` has the diagonals apex -> apex + 2 .. apex + n - 2. Enumerating the case
  // tables shows a fan always suffices: the only polygons with two non-neighbouring vertices on
  // one face are hexagons and heptagons that cross an ambiguous face twice, and each has two or
  // three vertices off that face to fan from (docs/surface_rules.md).
  for (int apex = 0; apex < n; ++apex) {
    bool inside_the_cube = true;
    for (int step = 2; step <= n - 2 && inside_the_cube; ++step) {
      int other = apex + step;
      if (other >= n) other -= n;
      inside_the_cube = !share_a_cube_face(v[apex], v[other]);
    }
    if (inside_the_cube) return apex;
  }
  return -1;
}

bool triangulate_polygon(const PolygonGeometry& polygon, PolygonTriangles* triangles) {
  *triangles = PolygonTriangles{};
  const int apex = fan_apex(polygon);
  if (apex < 0) return false;
  const int n = polygon.vertex_count;
  for (int i = 1; i <= n - 2; ++i) {
    std::uint8_t* corners = triangles->corners[triangles->count++];
    corners[0] = static_cast<std::uint8_t>(apex);
    corners[1] = static_cast<std::uint8_t>((apex + i) % n);
    corners[2] = static_cast<std::uint8_t>((apex + i + 1) % n);
  }
  return true;
}

}  // namespace mvox
