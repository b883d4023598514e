#pragma once
// Classic marching cubes (Lorensen and Cline, "Marching Cubes: A High Resolution 3D Surface
// Construction Algorithm", SIGGRAPH 1987): the triangles of each of the 256 cube
// configurations, generated at compile time from the paper's 15 base configurations by the
// cube's symmetries and complement, as the paper does. The baseline that the paper's experiment
// compares marching voxels with (docs/design.md section 2).
//
// The base configurations and their triangles are written here from the geometry of Figure 3
// of that paper, in this project's corner and edge numbering (cube.h); the winding of the base
// triangles is computed, not typed. Every other configuration is found as the image of a base
// configuration under one of the 48 symmetries of the cube (rotations first, then mirrors), and
// only when none matches, as the image of a base configuration's complement. Lorensen and Cline
// used rotations only, hence two staircases that are mirror images; with mirrors the first
// reaches every configuration of the second, whose entry stays for completeness. Complementing
// keeps the triangles and swaps inside and outside, so on a face with two diagonal inner
// corners it joins the inner corners where the uncomplemented neighbour separates them: the
// holes the marching voxels paper points out.
#include <cstdint>

#include "cube.h"
#include "mvox/assert.h"

namespace mvox {

// The triangles of one configuration: `triangle_count` triples of cube edge ids, each wound
// counter-clockwise seen from outside (outward normal from inner to outer, as polygons are).
struct MarchingCubesCase {
  static constexpr int kMaxTriangles = 5;
  std::uint8_t triangle_count = 0;
  std::uint8_t edges[3 * kMaxTriangles] = {};
};

struct MarchingCubesTable {
  MarchingCubesCase cases[256];
  // How each configuration was obtained: 0..14 = base configuration, and whether from its
  // complement. Kept for the tests and the documentation, not used by the engine.
  std::uint8_t base[256] = {};
  bool complemented[256] = {};
};

namespace marching_cubes_detail {

// A base configuration: its inner corners (a corner set, cube.h) and its triangles as edge ids,
// in any winding. Lorensen and Cline number them 0..14; the names say what the inner corners
// form.
struct BaseCase {
  const char* name;
  unsigned corners;
  std::uint8_t triangle_count;
  std::uint8_t edges[3 * MarchingCubesCase::kMaxTriangles];
};

constexpr unsigned corners_of(int a, int b = -1, int c = -1, int d = -1) {
  unsigned set = 1u << a;
  if (b >= 0) set |= 1u << b;
  if (c >= 0) set |= 1u << c;
  if (d >= 0) set |= 1u << d;
  return set;
}

// Edge ids (cube.h): x-edges 0: corners 0-1, 1: 2-3, 2: 4-5, 3: 6-7; y-edges 4: 0-2, 5: 1-3,
// 6: 4-6, 7: 5-7; z-edges 8: 0-4, 9: 1-5, 10: 2-6, 11: 3-7.
// Corners: 0 (0,0,0), 1 (1,0,0), 2 (0,1,0), 3 (1,1,0), 4 (0,0,1), 5 (1,0,1), 6 (0,1,1), 7 (1,1,1).
constexpr BaseCase kBaseCases[15] = {
    {"no inner corner", 0, 0, {}},
    {"one corner", corners_of(0), 1, {0, 4, 8}},
    {"two corners along an edge", corners_of(0, 1), 2, {4, 8, 9, 4, 9, 5}},
    {"two corners diagonal on a face", corners_of(0, 3), 2, {0, 4, 8, 1, 5, 11}},
    {"two corners diagonal through the cube", corners_of(0, 7), 2, {0, 4, 8, 3, 7, 11}},
    {"three corners on a face", corners_of(0, 1, 2), 3, {8, 9, 5, 8, 5, 1, 8, 1, 10}},
    {"an edge and the far corner", corners_of(0, 1, 7), 3, {4, 8, 9, 4, 9, 5, 3, 7, 11}},
    {"three corners diagonal to each other", corners_of(1, 2, 4), 3, {0, 5, 9, 1, 4, 10, 2, 6, 8}},
    {"a face", corners_of(0, 1, 2, 3), 2, {8, 9, 11, 8, 11, 10}},
    {"a corner and its three neighbours",
     corners_of(0, 1, 2, 4),
     4,
     {1, 10, 6, 6, 2, 9, 9, 5, 1, 1, 6, 9}},
    {"two opposite edges", corners_of(0, 1, 6, 7), 4, {4, 8, 9, 4, 9, 5, 6, 10, 11, 6, 11, 7}},
    {"a staircase x, y, z", corners_of(0, 1, 3, 7), 4, {8, 9, 7, 8, 7, 3, 8, 3, 1, 8, 1, 4}},
    {"three corners on a face and the far corner",
     corners_of(0, 1, 2, 7),
     4,
     {8, 9, 5, 8, 5, 1, 8, 1, 10, 3, 7, 11}},
    {"four corners diagonal to each other",
     corners_of(0, 3, 5, 6),
     4,
     {0, 4, 8, 1, 5, 11, 2, 7, 9, 3, 6, 10}},
    {"a staircase y, x, z", corners_of(0, 2, 3, 7), 4, {8, 0, 5, 8, 5, 7, 8, 7, 3, 8, 3, 10}},
};

// The point where cube edge `e` is cut, taking every cut at its midpoint: twice the coordinates,
// so that they stay integers.
constexpr int doubled_midpoint(int e, int axis) {
  return cube::corner_bit(cube::edge_low_corner(e), axis) +
         cube::corner_bit(cube::edge_high_corner(e), axis);
}

// Whether triangle (a, b, c) faces the outer side of `inner`: its normal by the right-hand rule
// has a component along its vertices' inner-to-outer directions that is positive or zero, and
// not zero for all three. A base triangle for which they disagree is a typing error, reported
// at compile time.
constexpr bool faces_outward(unsigned inner, int a, int b, int c) {
  int u[3] = {}, v[3] = {};
  for (int k = 0; k < 3; ++k) {
    u[k] = doubled_midpoint(b, k) - doubled_midpoint(a, k);
    v[k] = doubled_midpoint(c, k) - doubled_midpoint(a, k);
  }
  const int normal[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                         u[0] * v[1] - u[1] * v[0]};
  int positive = 0, negative = 0;
  const int edges[3] = {a, b, c};
  for (int e : edges) {
    const int axis = cube::edge_axis(e);
    const bool lower_inner = (inner >> cube::edge_low_corner(e) & 1) != 0;
    MVOX_ASSERT(lower_inner != ((inner >> cube::edge_high_corner(e) & 1) != 0));
    const int along = lower_inner ? normal[axis] : -normal[axis];
    positive += along > 0;
    negative += along < 0;
  }
  MVOX_ASSERT((positive > 0) != (negative > 0));
  return positive > 0;
}

// One of the 48 symmetries of the cube: coordinate i of the image is coordinate axes[i] of the
// original, flipped when bit i of `flips` is set.
struct Symmetry {
  int axes[3];
  int flips;

  constexpr int map_corner(int corner) const {
    int image = 0;
    for (int i = 0; i < 3; ++i)
      image |= (cube::corner_bit(corner, axes[i]) ^ (flips >> i & 1)) << i;
    return image;
  }
  constexpr unsigned map_corners(unsigned set) const {
    unsigned image = 0;
    for (int c = 0; c < cube::kCorners; ++c)
      if (set >> c & 1) image |= 1u << map_corner(c);
    return image;
  }
  constexpr int map_edge(int e) const {
    const int a = map_corner(cube::edge_low_corner(e)), b = map_corner(cube::edge_high_corner(e));
    const int lower = a < b ? a : b, difference = a ^ b;
    const int axis = difference == 1 ? 0 : difference == 2 ? 1 : 2;
    return cube::edge_from_corner(lower, axis);
  }
  // A mirror (determinant -1) turns counter-clockwise into clockwise.
  constexpr bool is_mirror() const {
    const bool odd_permutation = (axes[0] == 0) + (axes[1] == 1) + (axes[2] == 2) == 1;
    const int flipped = (flips & 1) + (flips >> 1 & 1) + (flips >> 2 & 1);
    return odd_permutation != (flipped % 2 == 1);
  }
};

// The 48 symmetries, the 24 rotations first.
struct Symmetries {
  Symmetry all[48] = {};
};

constexpr Symmetries cube_symmetries() {
  constexpr int kPermutations[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                       {1, 0, 2}, {0, 2, 1}, {2, 1, 0}};
  Symmetries result;
  int rotations = 0, mirrors = 24;
  for (const auto& p : kPermutations)
    for (int flips = 0; flips < 8; ++flips) {
      const Symmetry s{{p[0], p[1], p[2]}, flips};
      result.all[s.is_mirror() ? mirrors++ : rotations++] = s;
    }
  MVOX_ASSERT(rotations == 24 && mirrors == 48);
  return result;
}

// The triangles of base case `base` carried to the configuration `symmetry` maps it to (or its
// complement), wound counter-clockwise seen from outside.
constexpr MarchingCubesCase transformed_case(const BaseCase& base, const Symmetry& symmetry,
                                             bool complement) {
  MarchingCubesCase result;
  result.triangle_count = base.triangle_count;
  for (int t = 0; t < base.triangle_count; ++t) {
    const std::uint8_t* tri = base.edges + 3 * t;
    // Base triangles are wound outward for the base corners; complementing swaps outward.
    const bool reverse = !faces_outward(base.corners, tri[0], tri[1], tri[2]) !=
                         (symmetry.is_mirror() != complement);
    const int order[3] = {0, reverse ? 2 : 1, reverse ? 1 : 2};
    for (int k = 0; k < 3; ++k)
      result.edges[3 * t + k] = static_cast<std::uint8_t>(symmetry.map_edge(tri[order[k]]));
  }
  return result;
}

}  // namespace marching_cubes_detail

constexpr MarchingCubesTable build_marching_cubes_table() {
  using namespace marching_cubes_detail;
  constexpr Symmetries symmetries = cube_symmetries();
  MarchingCubesTable table;
  bool found[256] = {};
  // Every base configuration under every symmetry, the first image of a configuration winning.
  // Uncomplemented images come first, so that a configuration with at most four inner corners
  // always keeps its inner corners apart on an ambiguous face.
  for (int complement = 0; complement < 2; ++complement)
    for (int b = 0; b < 15; ++b)
      for (const Symmetry& s : symmetries.all) {
        const unsigned image = s.map_corners(kBaseCases[b].corners);
        const unsigned config = complement ? ~image & 0xFFu : image;
        if (found[config]) continue;
        table.cases[config] = transformed_case(kBaseCases[b], s, complement != 0);
        table.base[config] = static_cast<std::uint8_t>(b);
        table.complemented[config] = complement != 0;
        found[config] = true;
      }
  for (bool f : found) MVOX_ASSERT(f);
  return table;
}

// The table, generated by the compiler (marching_cubes_table.cpp).
const MarchingCubesTable& marching_cubes_table();

// The name of Lorensen and Cline's base configuration `base` (0..14).
const char* marching_cubes_base_name(int base);

}  // namespace mvox
