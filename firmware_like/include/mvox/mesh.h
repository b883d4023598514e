#pragma once
// The indexed mesh the engine emits: vertices once each, polygons referring to them by index.
#include <cstdint>

namespace mvox {

// A polygon has 3 to 7 vertices (the loops a 2x2x2 cube can hold; docs/design.md section 4).
// Marching cubes emits triangles only.
constexpr int kMaxPolygonVertices = 7;

// At most this many vertices per mesh: their indices 0 .. 2^31 - 1 fit the signed 32-bit
// integers that PLY and most mesh consumers index with.
constexpr std::uint64_t kMaxVertexCount = std::uint64_t{1} << 31;

// Axis of the voxel pair a vertex sits between: x, y or z neighbours.
enum class Axis : std::uint8_t { x = 0, y = 1, z = 2 };

// A surface vertex at the midpoint of an inner voxel and an outer 6-adjacent voxel (marching
// voxels), or elsewhere on the segment between them (marching cubes interpolates).
// Coordinates are in voxel units: x = column, y = row, z = slice index, so the midpoint of
// voxels (3,4,5) and (4,4,5) is (3.5, 4, 5). The engine numbers vertices 0, 1, 2, ... in the
// order they are emitted. `inner_is_lower` tells whether the inner voxel is the one with the
// smaller coordinate along `axis`; with it a sink can find the outward direction.
struct Vertex {
  float x = 0, y = 0, z = 0;
  Axis axis = Axis::x;
  bool inner_is_lower = false;
};

// Vertex indices wound counter-clockwise seen from outside (outward normal by the right-hand
// rule, from inner to outer). Every index was emitted in a vertex batch before this polygon.
struct Polygon {
  std::uint8_t vertex_count = 0;
  std::uint32_t vertices[kMaxPolygonVertices] = {};
};

// The same polygon with its vertices by value, in the same order: for sinks that draw rather
// than index (the renderer), so that they need not keep every vertex of the last layers.
struct PolygonGeometry {
  std::uint8_t vertex_count = 0;
  Vertex vertices[kMaxPolygonVertices] = {};
};

}  // namespace mvox
