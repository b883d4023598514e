#pragma once
// The fast engine's data: the polygons of each of the 256 cube configurations, as loops of cube
// edge ids (cube.h). Generated at compile time by running the literal merge passes
// (cube_merge.h) on every configuration; nothing here is typed in by hand.
#include "cube_merge.h"
#include "mvox/surface_method.h"

namespace mvox {

// One polygon of a case as the fast engine copies it into a batch: every one of the seven
// vertex slots names a cube edge, those past vertex_count repeat the first, so that filling a
// polygon is seven loads and stores with no loop over its size (whose length the branch
// predictor cannot guess). The repeated slots are outside the polygon and never read.
struct PolygonRecord {
  std::uint8_t vertex_count = 0;
  std::uint8_t edges[kMaxPolygonVertices] = {};
};

struct CaseRecords {
  std::uint8_t polygon_count = 0;
  PolygonRecord polygons[CubePolygons::kMaxPolygons] = {};
};

struct CaseTable {
  CubePolygons cases[256];
  CaseRecords records[256];  // the same polygons, as fixed-size records
};

constexpr CaseRecords case_records(const CubePolygons& polygons) {
  CaseRecords records;
  records.polygon_count = polygons.polygon_count;
  int offset = 0;
  for (int p = 0; p < polygons.polygon_count; ++p) {
    PolygonRecord& record = records.polygons[p];
    record.vertex_count = polygons.polygon_sizes[p];
    for (int i = 0; i < kMaxPolygonVertices; ++i)
      record.edges[i] = polygons.edges[offset + (i < record.vertex_count ? i : 0)];
    offset += record.vertex_count;
  }
  return records;
}

constexpr CaseTable build_case_table(SurfaceRule rule) {
  CaseTable table;
  for (unsigned config = 0; config < 256; ++config) {
    table.cases[config] = cube_polygons(config, rule);
    table.records[config] = case_records(table.cases[config]);
  }
  return table;
}

const CaseTable& case_table(SurfaceRule rule);

}  // namespace mvox
