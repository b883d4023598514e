// Times mvox's in-memory extraction of one of the paper's datasets, for bench/compare_peers.py,
// which runs it between the runs of VTK and scikit-image and so needs mvox as a separate
// process that prints machine-readable figures.
//
//   mvox_bench_extract_once --dataset NAME [--runs K] [--datasets DIR] [--method voxels|cubes]
//   mvox_bench_extract_once --list [--datasets DIR]
//
// The first form decodes the dataset into memory (not timed), extracts once to warm caches and
// page in the code, then K times (default 1), each into a sink that only counts, and prints one
// JSON object: the volume's size, the threshold, vertex and polygon counts, and the wall and CPU
// time of each run in ms. The second prints one JSON object per line for each of the paper's
// datasets, present or not: its name, inputs, raw format and threshold, so that the Python side
// reads the same files at the same threshold without a second copy of that table.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "in_memory_extract.h"
#include "paper_datasets.h"
#include "write/stats_json.h"

namespace mvox::bench {
namespace {

// The surface methods --method accepts and the engine options each needs.
struct Method {
  const char* name;
  void (*configure)(EngineOptions& options);
};
const Method kMethods[] = {
    {"voxels", [](EngineOptions&) {}},
    {"cubes", [](EngineOptions& options) { options.method = SurfaceMethod::cubes; }},
};

const Method* find_method(const std::string& name) {
  for (const Method& method : kMethods)
    if (name == method.name) return &method;
  return nullptr;
}

std::string json_list(const std::vector<double>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    char number[32];
    std::snprintf(number, sizeof number, "%s%.4f", i ? ", " : "", values[i]);
    text += number;
  }
  return text + "]";
}

void list_datasets(const std::string& root) {
  for (const PaperDataset& dataset : all_paper_datasets(root)) {
    std::string inputs;
    for (const std::string& input : dataset.inputs)
      inputs += (inputs.empty() ? "" : ", ") + json_string(input);
    std::printf(
        "{\"name\": %s, \"present\": %s, \"inputs\": [%s], \"raw\": %s, \"threshold\": %g}\n",
        json_string(dataset.name).c_str(), dataset_present(dataset) ? "true" : "false",
        inputs.c_str(), json_string(dataset.raw_spec).c_str(), dataset.threshold);
  }
}

// Returns the process exit code.
int time_dataset(const PaperDataset& dataset, const Method& method, int runs) {
  const LoadedVolume volume = load_dataset(dataset);
  EngineOptions options;
  method.configure(options);
  EngineCounters counters;
  std::vector<double> wall_ms, cpu_ms;
  const double warmup_s = extract_in_memory(volume, dataset.threshold, options, &counters);
  for (int run = 0; run < runs && warmup_s >= 0; ++run) {
    const std::clock_t cpu_start = std::clock();  // process CPU time: shows one thread at work
    const double seconds = extract_in_memory(volume, dataset.threshold, options, &counters);
    if (seconds < 0) break;
    cpu_ms.push_back(1e3 * double(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    wall_ms.push_back(1e3 * seconds);
  }
  if (int(wall_ms.size()) != runs) {
    std::fprintf(stderr, "mvox_bench_extract_once: %s: the engine refused the volume\n",
                 dataset.name.c_str());
    return 1;
  }
  const VolumeInfo& info = volume.info;
  std::printf(
      "{\"dataset\": %s, \"method\": %s, \"width\": %u, \"height\": %u, \"depth\": %u, "
      "\"threshold\": %g, \"vertices\": %llu, \"polygons\": %llu, \"warmup_ms\": %.4f, "
      "\"times_ms\": %s, \"cpu_ms\": %s}\n",
      json_string(dataset.name).c_str(), json_string(method.name).c_str(), info.width, info.height,
      info.depth, dataset.threshold, (unsigned long long)counters.vertices,
      (unsigned long long)counters.polygons, 1e3 * warmup_s, json_list(wall_ms).c_str(),
      json_list(cpu_ms).c_str());
  return 0;
}

int usage(const char* program) {
  std::fprintf(stderr,
               "usage: %s --dataset NAME [--runs K] [--datasets DIR] [--method voxels|cubes]\n"
               "       %s --list [--datasets DIR]\n",
               program, program);
  return 2;
}

}  // namespace
}  // namespace mvox::bench

int main(int argc, char** argv) {
  using namespace mvox::bench;
  std::string root = MVOX_SHARED_DATASETS;
  std::string name;
  std::string method_name = "voxels";
  int runs = 1;
  bool list = false;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--list"))
      list = true;
    else if (!std::strcmp(argv[i], "--dataset") && has_value)
      name = argv[++i];
    else if (!std::strcmp(argv[i], "--datasets") && has_value)
      root = argv[++i];
    else if (!std::strcmp(argv[i], "--method") && has_value)
      method_name = argv[++i];
    else if (!std::strcmp(argv[i], "--runs") && has_value && std::atoi(argv[i + 1]) >= 1)
      runs = std::atoi(argv[++i]);
    else
      return usage(argv[0]);
  }
  if (list) {
    list_datasets(root);
    return 0;
  }
  const Method* method = find_method(method_name);
  if (name.empty() || !method) return usage(argv[0]);
  try {
    for (const PaperDataset& dataset : all_paper_datasets(root)) {
      if (dataset.name != name) continue;
      if (!dataset_present(dataset)) {
        std::fprintf(stderr, "mvox_bench_extract_once: %s: not found under %s\n", name.c_str(),
                     root.c_str());
        return 1;
      }
      return time_dataset(dataset, *method, runs);
    }
    std::fprintf(stderr, "mvox_bench_extract_once: no dataset named %s\n", name.c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mvox_bench_extract_once: %s\n", e.what());
    return 1;
  }
}
