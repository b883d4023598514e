#pragma once
// Geometry of one cube of 2x2x2 voxels: the unit every polygon lives in (docs/design.md section 2).
//
// Corner c = bx | by << 1 | bz << 2, where b* = 0 is the lower voxel along that axis.
// Edges (each hosts at most one vertex, the midpoint of its two corners):
//   0..3   x-edges, (by, bz) = (e & 1, e >> 1)
//   4..7   y-edges, (bx, bz) = ((e - 4) & 1, (e - 4) >> 1)
//   8..11  z-edges, (bx, by) = ((e - 8) & 1, (e - 8) >> 1)
// Faces f = 2 * axis + side hold the four corners whose coordinate on `axis` equals `side`.
#include <cstdint>

namespace mvox::cube {

constexpr int kCorners = 8;
constexpr int kEdges = 12;
constexpr int kFaces = 6;

constexpr int corner_bit(int corner, int axis) { return (corner >> axis) & 1; }

// Axis along which edge `e` runs (0 = x, 1 = y, 2 = z).
constexpr int edge_axis(int e) { return e >> 2; }

// The corner at the lower end of edge `e`; the upper end adds 1 << edge_axis(e).
constexpr int edge_low_corner(int e) {
  const int a = e & 1, b = (e >> 1) & 1;  // the two coordinates across the edge, in axis order
  switch (edge_axis(e)) {
    case 0: return a << 1 | b << 2;  // (by, bz)
    case 1: return a | b << 2;       // (bx, bz)
    default: return a | b << 1;      // (bx, by)
  }
}
constexpr int edge_high_corner(int e) { return edge_low_corner(e) | 1 << edge_axis(e); }

// The edge along `axis` whose lower end is `corner` (whose bit on `axis` must be 0).
constexpr int edge_from_corner(int corner, int axis) {
  switch (axis) {
    case 0: return corner_bit(corner, 1) | corner_bit(corner, 2) << 1;
    case 1: return 4 + (corner_bit(corner, 0) | corner_bit(corner, 2) << 1);
    default: return 8 + (corner_bit(corner, 0) | corner_bit(corner, 1) << 1);
  }
}

// The edge along `axis` that touches `corner` (either end).
constexpr int edge_at_corner(int corner, int axis) {
  return edge_from_corner(corner & ~(1 << axis), axis);
}

constexpr bool edge_on_face(int e, int face) {
  const int axis = face >> 1, side = face & 1;
  return corner_bit(edge_low_corner(e), axis) == side &&
         corner_bit(edge_high_corner(e), axis) == side;
}

// The one face holding both edges, or -1. Distinct edges share at most one face.
constexpr int shared_face(int e1, int e2) {
  for (int f = 0; f < kFaces; ++f)
    if (e1 != e2 && edge_on_face(e1, f) && edge_on_face(e2, f)) return f;
  return -1;
}

// The two faces that hold edge `e`, lower face index first.
constexpr int edge_face(int e, int which) {
  int found = 0;
  for (int f = 0; f < kFaces; ++f)
    if (edge_on_face(e, f) && found++ == which) return f;
  return -1;
}

// The four corners of `face` in cyclic order around it.
constexpr int face_corner(int face, int i) {
  const int axis = face >> 1, side = face & 1;
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  constexpr int kU[4] = {0, 1, 1, 0}, kV[4] = {0, 0, 1, 1};
  return side << axis | kU[i] << u | kV[i] << v;
}

// True when `face` holds exactly two inner corners lying diagonally: the ambiguous face, where
// the merge rules keep the two inner voxels apart (they share no vertex).
constexpr bool face_is_ambiguous(unsigned config, int face) {
  const bool c0 = config >> face_corner(face, 0) & 1, c1 = config >> face_corner(face, 1) & 1;
  const bool c2 = config >> face_corner(face, 2) & 1, c3 = config >> face_corner(face, 3) & 1;
  return c0 == c2 && c1 == c3 && c0 != c1;
}

// The edges of a cube that carry a vertex in `config`: those whose two corners differ. Bit e is
// edge e.
constexpr std::uint16_t cut_edges(unsigned config) {
  std::uint16_t cut = 0;
  for (int e = 0; e < kEdges; ++e)
    if ((config >> edge_low_corner(e) & 1) != (config >> edge_high_corner(e) & 1))
      cut = static_cast<std::uint16_t>(cut | 1u << e);
  return cut;
}

constexpr int inner_count(unsigned config) {
  int n = 0;
  for (int c = 0; c < kCorners; ++c) n += config >> c & 1;
  return n;
}

}  // namespace mvox::cube
