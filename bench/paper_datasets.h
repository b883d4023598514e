#pragma once
// The paper's three volumes as found in ../shared/datasets, with the thresholds and voxel
// spacings the benchmarks use, how to open each with the host readers, and how to decode one
// whole into memory so that a benchmark times the engine and not the reader.
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/raw/raw_format.h"

namespace mvox::bench {

struct PaperDataset {
  std::string name;                 // "CThead"
  std::vector<std::string> inputs;  // as given to `mvox extract`
  std::string raw_spec;             // "" for image stacks
  double threshold = 0;
  std::string why_threshold;
  // Voxel size along x, y, z (the readers say 1,1,1: raw files and images carry none). Only
  // the shape of the surface depends on it (normals, pictures), not the polygon counts.
  std::array<double, 3> spacing = {1, 1, 1};
};

// All three datasets as they would be found under `root` (normally ../shared/datasets), whether
// present or not.
std::vector<PaperDataset> all_paper_datasets(const std::string& root);

// Whether the folder of `dataset` exists (its files may still be unreadable).
bool dataset_present(const PaperDataset& dataset);

// The datasets under `root` (normally ../shared/datasets). Missing ones are skipped.
std::vector<PaperDataset> paper_datasets(const std::string& root);

std::unique_ptr<SliceSource> open_dataset(const PaperDataset& dataset);

// A whole volume decoded into memory.
struct LoadedVolume {
  VolumeInfo info;                   // the reader's, with the dataset's spacing
  std::vector<unsigned char> bytes;  // slices one after another, rows packed
  std::size_t slice_bytes = 0;

  SliceView slice(std::uint32_t z) const;
};

// A decoded volume handed out slice by slice, as a reader would: to time the engine (and what
// follows it) through stream_volume without the reader's cost.
class LoadedVolumeSource final : public SliceSource {
 public:
  explicit LoadedVolumeSource(const LoadedVolume& volume) : volume_(volume) {}
  const VolumeInfo& info() const override { return volume_.info; }
  bool next_slice(SliceView* slice) override {
    if (next_ >= volume_.info.depth) return false;
    *slice = volume_.slice(next_++);
    return true;
  }

 private:
  const LoadedVolume& volume_;
  std::uint32_t next_ = 0;
};

// Reads and decodes every slice of `dataset`. Throws what the readers throw.
LoadedVolume load_dataset(const PaperDataset& dataset);

// The median of `values` (the mean of the middle two for an even count); 0 when empty.
double median(std::vector<double> values);

}  // namespace mvox::bench
