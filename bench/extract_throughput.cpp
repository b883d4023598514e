// Extraction throughput of the fast and literal engines on the paper's three datasets:
// in memory (slices already decoded; the engine and a sink that only counts) and end to end
// (reading the files, extracting, writing binary PLY). Runs are interleaved between the engines
// and the median of each is reported, so a noisy shared machine biases both alike.
//
//   mvox_bench_extract [--datasets DIR] [--runs N] [--scratch DIR]
//
// Prints a Markdown table on standard output.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_arguments.h"
#include "error.h"
#include "in_memory_extract.h"
#include "paper_datasets.h"
#include "pipeline/mesh_job.h"
#include "pipeline/pipeline.h"
#include "write/mesh/ply_writer.h"

namespace mvox::bench {
namespace {

using Clock = std::chrono::steady_clock;

double extract_end_to_end(const PaperDataset& dataset, EngineKind kind, const std::string& output) {
  const auto start = Clock::now();
  auto source = open_dataset(dataset);
  EngineOptions options;
  options.kind = kind;
  PlyWriter writer(output);
  const PipelineResult result =
      run_pipeline(*source, dataset.threshold, options, writer, dataset.name);
  if (result.status != Status::ok) return -1;
  writer.finish();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace
}  // namespace mvox::bench

int main(int argc, char** argv) {
  using namespace mvox;
  using namespace mvox::bench;
  BenchArguments arguments;
  if (!parse_bench_arguments(argc, argv, MVOX_SHARED_DATASETS, {"--scratch"}, &arguments)) return 2;
  const std::string root = arguments.datasets;
  const std::string scratch =
      arguments.value("--scratch", std::filesystem::temp_directory_path().string());
  const int runs = arguments.runs;
  try {
    const std::vector<PaperDataset> datasets = paper_datasets(root);
    if (datasets.empty()) {
      std::fprintf(stderr, "mvox_bench_extract: no dataset found under %s\n", root.c_str());
      return 1;
    }
    const std::string output = scratch + "/mvox_bench_extract.ply";
    EngineOptions fast_options, literal_options;
    literal_options.kind = EngineKind::literal;

    std::printf(
        "| dataset | voxels | threshold | vertices | polygons | fast, in memory | literal, in "
        "memory "
        "| fast/literal | fast, end to end | literal, end to end |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n");
    for (const PaperDataset& dataset : datasets) {
      const LoadedVolume volume = load_dataset(dataset);
      const double mvoxels =
          double(volume.info.width) * volume.info.height * volume.info.depth / 1e6;
      std::vector<double> fast_memory, literal_memory, fast_files, literal_files;
      EngineCounters fast_counters, literal_counters;
      for (int run = 0; run < runs; ++run) {  // interleaved, so drift hits both engines alike
        fast_memory.push_back(
            extract_in_memory(volume, dataset.threshold, fast_options, &fast_counters));
        literal_memory.push_back(
            extract_in_memory(volume, dataset.threshold, literal_options, &literal_counters));
        fast_files.push_back(extract_end_to_end(dataset, EngineKind::fast, output));
        literal_files.push_back(extract_end_to_end(dataset, EngineKind::literal, output));
      }
      if (fast_counters.polygons != literal_counters.polygons ||
          fast_counters.vertices != literal_counters.vertices) {
        std::fprintf(stderr, "%s: engines disagree\n", dataset.name.c_str());
        return 1;
      }
      const double fm = median(fast_memory), lm = median(literal_memory);
      const double ff = median(fast_files), lf = median(literal_files);
      std::printf(
          "| %s | %ux%ux%u %s | %g | %s | %s | %.0f Mvoxel/s (%.1f ms) | %.0f Mvoxel/s (%.0f ms) "
          "| %.0fx | %.0f Mvoxel/s (%.1f ms) | %.0f Mvoxel/s (%.0f ms) |\n",
          dataset.name.c_str(), volume.info.width, volume.info.height, volume.info.depth,
          sample_type_name(volume.info.type), dataset.threshold,
          grouped(fast_counters.vertices).c_str(), grouped(fast_counters.polygons).c_str(),
          mvoxels / fm, fm * 1e3, mvoxels / lm, lm * 1e3, lm / fm, mvoxels / ff, ff * 1e3,
          mvoxels / lf, lf * 1e3);
      std::fflush(stdout);
    }
    std::filesystem::remove(output);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mvox_bench_extract: %s\n", e.what());
    return 1;
  }
  return 0;
}
