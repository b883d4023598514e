#include "case_table.h"

namespace mvox {
namespace {

// constexpr forces the generation to happen in the compiler: the tables sit in read-only data,
// and a broken invariant in the merge passes is a compile error rather than a runtime surprise.
constexpr CaseTable kMergeRulesTable = build_case_table(SurfaceRule::merge_rules);
constexpr CaseTable kPaperTable1Table = build_case_table(SurfaceRule::paper_table1);

static_assert(kMergeRulesTable.cases[0].polygon_count == 0, "no inner voxel, no surface");
static_assert(kMergeRulesTable.cases[255].polygon_count == 0, "all inner, no surface");
static_assert(kMergeRulesTable.cases[1].polygon_count == 1 &&
                  kMergeRulesTable.cases[1].polygon_sizes[0] == 3,
              "one inner voxel gives its octant triangle");

}  // namespace

const CaseTable& case_table(SurfaceRule rule) {
  return rule == SurfaceRule::paper_table1 ? kPaperTable1Table : kMergeRulesTable;
}

}  // namespace mvox
