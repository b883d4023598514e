#include "labels/label_values.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace mvox {
namespace {

// Calls `visit(x, y, label)` for every sample of `slice` that is a label (> 0, whole, at most
// kMaxLabel), with the sample type dispatched once.
template <class Visit>
void for_each_label(const SliceView& slice, Visit&& visit) {
  const auto* base = static_cast<const unsigned char*>(slice.samples);
  for (std::uint32_t y = 0; y < slice.height; ++y) {
    const unsigned char* row = base + std::size_t{y} * slice.row_stride_bytes;
    switch (slice.type) {
      case SampleType::u8:
        for (std::uint32_t x = 0; x < slice.width; ++x)
          if (row[x] != 0) visit(x, y, std::uint32_t{row[x]});
        break;
      case SampleType::u16:
      case SampleType::i16:
        for (std::uint32_t x = 0; x < slice.width; ++x) {
          std::uint16_t bits;
          std::memcpy(&bits, row + 2 * x, 2);
          if (slice.type == SampleType::i16 && (bits & 0x8000u) != 0) continue;  // negative
          if (bits != 0) visit(x, y, std::uint32_t{bits});
        }
        break;
      case SampleType::f32:
        for (std::uint32_t x = 0; x < slice.width; ++x) {
          float value;
          std::memcpy(&value, row + 4 * x, 4);
          if (value >= 1.0f && value <= static_cast<float>(kMaxLabel) &&
              value == std::floor(value))
            visit(x, y, static_cast<std::uint32_t>(value));
        }
        break;
    }
  }
}

}  // namespace

bool LabelChoice::wants(std::uint32_t label) const {
  return all || std::binary_search(listed.begin(), listed.end(), label);
}

std::string parse_label_choice(const std::string& text, LabelChoice* choice) {
  *choice = LabelChoice();
  if (text.empty() || text == "all") return "";
  choice->all = false;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos
                                                                           : comma - start);
    char* end = nullptr;
    const unsigned long long value = std::strtoull(item.c_str(), &end, 10);
    if (item.empty() || item[0] < '0' || item[0] > '9' || *end != '\0' || value < 1 ||
        value > kMaxLabel)
      return "'" + item + "' is not a label: labels are whole numbers from 1 to " +
             std::to_string(kMaxLabel) + ", e.g. --labels 1,4,7";
    choice->listed.push_back(static_cast<std::uint32_t>(value));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  std::sort(choice->listed.begin(), choice->listed.end());
  choice->listed.erase(std::unique(choice->listed.begin(), choice->listed.end()),
                       choice->listed.end());
  return "";
}

const std::vector<std::uint32_t>& LabelSlices::labels_in(const SliceView& slice) {
  present_.clear();
  if (slice.type == SampleType::f32) {
    for_each_label(slice, [&](std::uint32_t, std::uint32_t, std::uint32_t label) {
      if (present_.empty() || present_.back() != label) present_.push_back(label);
    });
    std::sort(present_.begin(), present_.end());
    present_.erase(std::unique(present_.begin(), present_.end()), present_.end());
  } else {
    // Integer samples: one flag per 16-bit value, cleared for what was set.
    seen_.resize(65536);
    for_each_label(slice, [&](std::uint32_t, std::uint32_t, std::uint32_t label) {
      if (!seen_[label]) {
        seen_[label] = 1;
        present_.push_back(label);
      }
    });
    for (const std::uint32_t label : present_) seen_[label] = 0;
    std::sort(present_.begin(), present_.end());
  }
  if (!choice_.all)
    present_.erase(std::remove_if(present_.begin(), present_.end(),
                                  [&](std::uint32_t label) { return !choice_.wants(label); }),
                   present_.end());
  return present_;
}

void LabelSlices::fill_masks(const SliceView& slice, const std::vector<std::uint32_t>& labels,
                             const std::vector<std::uint8_t*>& masks) {
  const std::size_t pixels = std::size_t{slice.width} * slice.height;
  for (std::uint8_t* mask : masks) std::memset(mask, 0, pixels);
  if (labels.empty()) return;
  auto mask_of = [&](std::uint32_t label) -> std::uint8_t* {
    const auto at = std::lower_bound(labels.begin(), labels.end(), label);
    return at != labels.end() && *at == label ? masks[static_cast<std::size_t>(at - labels.begin())]
                                              : nullptr;
  };
  std::uint32_t last_label = 0;
  std::uint8_t* last_mask = nullptr;
  for_each_label(slice, [&](std::uint32_t x, std::uint32_t y, std::uint32_t label) {
    // Neighbouring voxels mostly share a label: remember the last lookup.
    if (label != last_label) {
      last_label = label;
      last_mask = mask_of(label);
    }
    if (last_mask) last_mask[std::size_t{y} * slice.width + x] = 1;
  });
}

}  // namespace mvox
