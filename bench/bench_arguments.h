#pragma once
// The command line the benchmark programs share: --datasets DIR and --runs N, plus options of
// their own, each taking one value.
#include <map>
#include <string>
#include <vector>

namespace mvox::bench {

struct BenchArguments {
  std::string datasets;                    // the folder holding the paper's datasets
  int runs = 5;                            // runs per figure, >= 1
  std::map<std::string, std::string> own;  // the program's own options given, by name

  // The value of the program's own option `name`, or `fallback` when it was not given.
  std::string value(const std::string& name, const std::string& fallback = "") const;
};

// Parses argv. `own_options` are the program's own option names ("--chart"). On an unknown
// option or a missing value prints a usage line and returns false (exit with 2).
bool parse_bench_arguments(int argc, char** argv, const std::string& default_datasets,
                           const std::vector<std::string>& own_options, BenchArguments* arguments);

}  // namespace mvox::bench
