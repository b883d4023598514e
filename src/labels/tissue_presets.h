#pragma once
// --tissue: CT tissues as ranges of Hounsfield units, for CT series. A tissue with an upper bound
// (fat, soft tissue) is extracted as the surface of the voxels inside its range
// (value_range_source.h); one without (bone, skin) is an ordinary threshold.
//
// The values (docs/design.md says why):
//   bone         >= 300 HU   cancellous bone begins about +300 HU, cortical bone reaches +1900
//   skin         >= -300 HU  the body against air (-1000) and lung (-900 .. -500), fat included
//   fat          -190 .. -30 HU    adipose tissue, the window of CT body-composition studies
//   soft-tissue  -29 .. 150 HU     skeletal muscle and organs, the same studies' muscle window
#include <limits>
#include <string>
#include <vector>

namespace mvox {

struct TissuePreset {
  const char* name;
  double low;   // inner: low <= value
  double high;  // and value <= high; +infinity: no upper bound (a threshold)
  bool range() const { return high != std::numeric_limits<double>::infinity(); }
};

const std::vector<TissuePreset>& tissue_presets();
// The preset called `name`, or nullptr.
const TissuePreset* find_tissue(const std::string& name);
// "bone, skin, fat, soft-tissue", for --help and messages.
std::string tissue_names();

}  // namespace mvox
