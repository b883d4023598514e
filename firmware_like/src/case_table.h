#pragma once
// The fast engine's data: the polygons of each of the 256 cube configurations, as loops of cube
// edge ids (cube.h). Generated at compile time by running the literal merge passes
// (cube_merge.h) on every configuration; nothing here is typed in by hand.
#include "cube_merge.h"
#include "mvox/engine.h"

namespace mvox {

struct CaseTable {
  CubePolygons cases[256];
};

constexpr CaseTable build_case_table(SurfaceRule rule) {
  CaseTable table;
  for (unsigned config = 0; config < 256; ++config)
    table.cases[config] = cube_polygons(config, rule);
  return table;
}

const CaseTable& case_table(SurfaceRule rule);

}  // namespace mvox
