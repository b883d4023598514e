#pragma once
// What MeshWriter checks of every polygon batch before it writes one: whether each polygon's
// size is in range, and the largest vertex index any polygon uses. One pass, no branch per
// polygon; with AVX2 (chosen at run time) one polygon's seven slots at a time.
#include <cstddef>
#include <cstdint>

#include "mvox/mesh.h"

namespace mvox {

struct PolygonScan {
  bool sizes_ok = true;       // every polygon has 3 to kMaxPolygonVertices vertices
  std::uint32_t highest = 0;  // the largest index among the first vertex_count slots of each
};

// The slots past a polygon's vertex_count, and the padding after the count, may hold anything:
// they are not read as indices. A polygon whose size is out of range still adds its first
// min(vertex_count, kMaxPolygonVertices) slots to `highest`.
PolygonScan scan_polygons(const Polygon* polygons, std::size_t count);

// The same, one slot at a time: the reference the fast scan is tested against.
PolygonScan scan_polygons_portable(const Polygon* polygons, std::size_t count);

}  // namespace mvox
