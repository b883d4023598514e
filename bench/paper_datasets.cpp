#include "paper_datasets.h"

#include <algorithm>
#include <filesystem>

#include "read/input_format.h"

namespace mvox::bench {

std::vector<PaperDataset> all_paper_datasets(const std::string& root) {
  return {
      {"CThead",
       {root + "/cthead/CThead.*"},
       "256x256:u16be",
       600,
       "skin/soft tissue against air (the issue's threshold)",
       // Voxel aspect 1:1:2 (Stanford's CThead.info): the paper's 225 slices are these 113
       // with one interpolated between each pair.
       {1, 1, 2}},
      {"engine",
       {root + "/engine/engine_256x256x128_uint8.raw"},
       "256x256x128:u8",
       100,
       "between the air peak (0-15) and the metal block (128-159)"},
      {"MRbrain",
       {root + "/mrbrain8bit/mrbrain-8bit*.png"},
       "",
       50,
       "between the background (0-15) and head tissue (16-95)",
       // Not stated for this 8-bit sagittal set; the 16-bit original's info gives 1:1:2, and
       // with it the rendered head is round (with 1:1:1 it is flattened side to side).
       {1, 1, 2}},
  };
}

bool dataset_present(const PaperDataset& dataset) {
  return std::filesystem::exists(std::filesystem::path(dataset.inputs[0]).parent_path());
}

std::vector<PaperDataset> paper_datasets(const std::string& root) {
  std::vector<PaperDataset> present;
  for (const PaperDataset& dataset : all_paper_datasets(root))
    if (dataset_present(dataset)) present.push_back(dataset);
  return present;
}

std::unique_ptr<SliceSource> open_dataset(const PaperDataset& dataset) {
  std::optional<RawFormat> raw;
  if (!dataset.raw_spec.empty()) raw = parse_raw_format(dataset.raw_spec);
  return open_slice_source(dataset.inputs, raw);
}

SliceView LoadedVolume::slice(std::uint32_t z) const {
  const std::size_t row_bytes = info.width * sample_bytes(info.type);
  return {bytes.data() + z * slice_bytes, info.width, info.height, row_bytes, info.type};
}

LoadedVolume load_dataset(const PaperDataset& dataset) {
  auto source = open_dataset(dataset);
  LoadedVolume volume;
  volume.info = source->info();
  for (int axis = 0; axis < 3; ++axis) volume.info.spacing[axis] = dataset.spacing[axis];
  const std::size_t row_bytes = volume.info.width * sample_bytes(volume.info.type);
  volume.slice_bytes = row_bytes * volume.info.height;
  SliceView slice;
  while (source->next_slice(&slice))
    for (std::uint32_t y = 0; y < slice.height; ++y) {
      const auto* row =
          static_cast<const unsigned char*>(slice.samples) + y * slice.row_stride_bytes;
      volume.bytes.insert(volume.bytes.end(), row, row + row_bytes);
    }
  volume.info.depth = static_cast<std::uint32_t>(volume.bytes.size() / volume.slice_bytes);
  return volume;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

}  // namespace mvox::bench
