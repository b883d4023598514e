#pragma once
// Test support: run the mvox binary as a user would, and a scratch directory per test.
#include <filesystem>
#include <string>
#include <vector>

namespace mvox::test {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // standard output and standard error together
};

// Runs `mvox ARGUMENTS` through the shell (so quoting works as in a terminal) from `directory`,
// after `prefix` (for instance "env -u DISPLAY").
CommandResult run_mvox(const std::string& arguments, const std::filesystem::path& directory,
                       const std::string& prefix = "");

// Runs `command_line` through the shell from `directory`, as run_mvox() does.
CommandResult run_command(const std::string& command_line, const std::filesystem::path& directory);

// One line of output, starting "mvox: error: ", mentioning `subject`, with exit code
// `exit_code` (1: the job failed, 2: a usage error, which adds a line pointing at --help).
void expect_one_line_error(const CommandResult& result, const std::string& subject,
                           int exit_code = 1);

// A fresh empty directory, removed with everything in it when the object goes away.
class ScratchDirectory {
 public:
  ScratchDirectory();
  ~ScratchDirectory();
  const std::filesystem::path& path() const { return path_; }
  std::string str() const { return path_.string(); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::string file(const std::string& name) const { return *this / name; }
  // Names of the entries, hidden ones included (a writer's temporaries are), sorted.
  std::vector<std::string> entries() const;
  // The same as one string: to check nothing unexpected (a temporary) was left behind.
  std::string listing() const;

 private:
  std::filesystem::path path_;
};

}  // namespace mvox::test
