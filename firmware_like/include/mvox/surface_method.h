#pragma once
// The choices of surface the engine makes, on their own so that the tables behind them
// (case_table.h, marching_cubes_table.h) need not include the engine.
#include <cstdint>

namespace mvox {

// Which surface is extracted.
enum class SurfaceMethod : std::uint8_t {
  // Marching voxels: polygons of 3 to 7 vertices, vertices at the midpoints of inner/outer voxel
  // pairs (docs/design.md section 2). The default.
  voxels,
  // Classic marching cubes (Lorensen and Cline, 1987), the paper's baseline: triangles from the
  // 256-entry table built from the 15 base configurations (marching_cubes_table.h), vertices
  // where the linearly interpolated samples cross the threshold. The same vertices, numbered
  // alike, as marching voxels (only their positions move along their edges). Leaves holes where
  // a complemented configuration meets an uncomplemented one across an ambiguous face.
  cubes,
};

// How marching voxels finds the polygons of each 2x2x2 cube. Both give identical output.
enum class EngineKind : std::uint8_t {
  fast,     // looks the cube up in a table generated from the literal merge passes (default)
  literal,  // runs the paper's triangle generation and x, y, z merge passes voxel by voxel
};

// Which surface the cube configurations get.
enum class SurfaceRule : std::uint8_t {
  // The merge rules of the paper applied as stated: closed, hole-free, inner voxels 6-connected
  // (docs/design.md section 2). The default.
  merge_rules,
  // The paper's Table 1 for five and six inner voxels (C5.1, C5.2, C6.2): the complementary
  // configuration's surface. Leaves holes where a cube face is ambiguous; for reproducing the
  // paper only.
  paper_table1,
};

}  // namespace mvox
