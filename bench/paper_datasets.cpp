#include "paper_datasets.h"

#include <filesystem>

#include "slice_source_factory.h"

namespace mvox::bench {

std::vector<PaperDataset> paper_datasets(const std::string& root) {
  const std::vector<PaperDataset> all = {
      {"CThead",
       {root + "/cthead/CThead.*"},
       "256x256:u16be",
       600,
       "skin/soft tissue against air (the issue's threshold)"},
      {"engine",
       {root + "/engine/engine_256x256x128_uint8.raw"},
       "256x256x128:u8",
       100,
       "between the air peak (0-15) and the metal block (128-159)"},
      {"MRbrain",
       {root + "/mrbrain8bit/mrbrain-8bit*.png"},
       "",
       50,
       "between the background (0-15) and head tissue (16-95)"},
  };
  std::vector<PaperDataset> present;
  for (const PaperDataset& dataset : all) {
    const std::string folder = std::filesystem::path(dataset.inputs[0]).parent_path().string();
    if (std::filesystem::exists(folder)) present.push_back(dataset);
  }
  return present;
}

std::unique_ptr<SliceSource> open_dataset(const PaperDataset& dataset) {
  std::optional<RawFormat> raw;
  if (!dataset.raw_spec.empty()) raw = parse_raw_format(dataset.raw_spec);
  return open_slice_source(dataset.inputs, raw);
}

}  // namespace mvox::bench
