#include "bench_arguments.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace mvox::bench {

std::string BenchArguments::value(const std::string& name, const std::string& fallback) const {
  const auto found = own.find(name);
  return found == own.end() ? fallback : found->second;
}

bool parse_bench_arguments(int argc, char** argv, const std::string& default_datasets,
                           const std::vector<std::string>& own_options, BenchArguments* arguments) {
  arguments->datasets = default_datasets;
  for (int i = 1; i < argc; i += 2) {
    const std::string name = argv[i];
    const bool known = name == "--datasets" || name == "--runs" ||
                       std::find(own_options.begin(), own_options.end(), name) != own_options.end();
    if (!known || i + 1 >= argc) {
      std::string usage = "usage: " + std::string(argv[0]) + " [--datasets DIR] [--runs N]";
      for (const std::string& option : own_options) usage += " [" + option + " VALUE]";
      std::fprintf(stderr, "%s\n", usage.c_str());
      return false;
    }
    const std::string value = argv[i + 1];
    if (name == "--datasets")
      arguments->datasets = value;
    else if (name == "--runs")
      arguments->runs = std::max(1, std::atoi(value.c_str()));
    else
      arguments->own[name] = value;
  }
  return true;
}

}  // namespace mvox::bench
