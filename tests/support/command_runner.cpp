#include "command_runner.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <random>
#include <vector>

namespace mvox::test {

CommandResult run_mvox(const std::string& arguments, const std::filesystem::path& directory,
                       const std::string& prefix) {
  return run_command(prefix + " '" MVOX_BINARY "' " + arguments, directory);
}

CommandResult run_command(const std::string& command_line,
                          const std::filesystem::path& directory) {
  const std::string command = "cd '" + directory.string() + "' && " + command_line + " 2>&1";
  CommandResult result;
  std::FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

ScratchDirectory::ScratchDirectory() {
  static std::atomic<unsigned> counter{0};
  std::random_device entropy;
  path_ = std::filesystem::temp_directory_path() /
          ("mvox_test_" + std::to_string(entropy()) + "_" + std::to_string(counter++));
  std::filesystem::create_directories(path_);
}

ScratchDirectory::~ScratchDirectory() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::vector<std::string> ScratchDirectory::entries() const {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(path_))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string ScratchDirectory::listing() const {
  std::string text;
  for (const auto& name : entries()) text += name + " ";
  return text;
}

void expect_one_line_error(const CommandResult& result, const std::string& subject, int exit_code) {
  EXPECT_EQ(result.exit_code, exit_code) << result.output;
  EXPECT_EQ(result.output.rfind("mvox: error: ", 0), 0u) << result.output;
  EXPECT_NE(result.output.find(subject), std::string::npos) << result.output;
  const std::size_t first_newline = result.output.find('\n');
  if (exit_code == 2)
    EXPECT_EQ(result.output.compare(first_newline + 1, 4, "Run "), 0) << result.output;
  else
    EXPECT_EQ(first_newline, result.output.size() - 1) << "more than one line: " << result.output;
}

}  // namespace mvox::test
