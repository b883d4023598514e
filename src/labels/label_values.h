#pragma once
// Label maps (segmentations): which labels a run extracts, which of them a slice holds, and a
// slice's inner-voxel mask for each. A voxel belongs to label L when its sample equals L; labels
// are positive integers (0 is background), integer samples or floats holding whole numbers.
#include <cstdint>
#include <string>
#include <vector>

#include "mvox/slice.h"

namespace mvox {

// --labels: every label present (`all`), or the ones listed.
struct LabelChoice {
  bool all = true;
  std::vector<std::uint32_t> listed;  // increasing, no repeats
  bool wants(std::uint32_t label) const;
};

// "" or "all": every label; "1,4,7": those. Returns an empty string, or the problem with `text`
// (a value that is not a whole number from 1 to 16777216, an empty item).
std::string parse_label_choice(const std::string& text, LabelChoice* choice);

// The largest label a float sample can hold exactly: labels above it are refused.
constexpr std::uint32_t kMaxLabel = 1u << 24;

// Finds the labels of one slice and builds their masks, in one pass over the samples.
class LabelSlices {
 public:
  explicit LabelSlices(const LabelChoice& choice) : choice_(choice) {}

  // The wanted labels present in `slice`, increasing: the result stays valid until the next
  // call. Float samples that are not whole numbers, and those above kMaxLabel, are no label.
  const std::vector<std::uint32_t>& labels_in(const SliceView& slice);

  // For each of `labels` (increasing), a width x height mask of `slice`, 1 where the sample
  // is that label and 0 elsewhere, written to masks[i] (each width * height bytes).
  void fill_masks(const SliceView& slice, const std::vector<std::uint32_t>& labels,
                  const std::vector<std::uint8_t*>& masks);

 private:
  LabelChoice choice_;
  std::vector<std::uint32_t> present_;
  std::vector<std::uint8_t> seen_;  // per 16-bit value, for integer samples
};

}  // namespace mvox
