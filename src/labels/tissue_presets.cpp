#include "labels/tissue_presets.h"

namespace mvox {

const std::vector<TissuePreset>& tissue_presets() {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  static const std::vector<TissuePreset> presets = {
      {"bone", 300, kNone},
      {"skin", -300, kNone},
      {"fat", -190, -30},
      {"soft-tissue", -29, 150},
  };
  return presets;
}

const TissuePreset* find_tissue(const std::string& name) {
  for (const TissuePreset& preset : tissue_presets())
    if (name == preset.name) return &preset;
  return nullptr;
}

std::string tissue_names() {
  std::string names;
  for (const TissuePreset& preset : tissue_presets())
    names += (names.empty() ? "" : ", ") + std::string(preset.name);
  return names;
}

}  // namespace mvox
