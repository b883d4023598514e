#pragma once
// The paper's three volumes as found in ../shared/datasets, with the thresholds the benchmarks
// use, and how to open each with the host readers.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "raw_format.h"

namespace mvox::bench {

struct PaperDataset {
  std::string name;                 // "CThead"
  std::vector<std::string> inputs;  // as given to `mvox extract`
  std::string raw_spec;             // "" for image stacks
  double threshold = 0;
  std::string why_threshold;
};

// The datasets under `root` (normally ../shared/datasets). Missing ones are skipped.
std::vector<PaperDataset> paper_datasets(const std::string& root);

std::unique_ptr<SliceSource> open_dataset(const PaperDataset& dataset);

}  // namespace mvox::bench
