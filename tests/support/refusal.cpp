#include "refusal.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <system_error>

#include "command_runner.h"

namespace fs = std::filesystem;

namespace mvox::test {

std::map<std::string, std::string> tree_snapshot(const fs::path& root) {
  std::map<std::string, std::string> entries;
  std::error_code error;
  for (fs::recursive_directory_iterator it(root, error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = fs::relative(it->path(), root).string();
    if (it->is_symlink()) {
      entries[name] = "link:" + fs::read_symlink(it->path()).string();
    } else if (it->is_directory()) {
      entries[name] = "directory";
    } else if (it->is_regular_file() && it->file_size() > (std::uintmax_t{64} << 20)) {
      entries[name] = "large file:" + std::to_string(it->file_size()) + ":" +
                      std::to_string(it->last_write_time().time_since_epoch().count());
    } else if (it->is_regular_file()) {
      std::ifstream in(it->path(), std::ios::binary);
      std::stringstream bytes;
      bytes << in.rdbuf();
      entries[name] = "file:" + bytes.str();
    } else {
      entries[name] = "other";
    }
  }
  return entries;
}

void expect_same_tree(const std::map<std::string, std::string>& before,
                      const std::map<std::string, std::string>& after) {
  for (const auto& [name, what] : after) {
    const auto was = before.find(name);
    if (was == before.end())
      ADD_FAILURE() << name << " was left behind";
    else if (was->second != what)
      ADD_FAILURE() << name << " was changed";
  }
  for (const auto& [name, what] : before)
    if (after.count(name) == 0) ADD_FAILURE() << name << " was removed";
}

void expect_refused(const fs::path& directory, const std::string& arguments,
                    const std::string& subject, const std::string& problem, int exit_code,
                    const std::string& prefix) {
  SCOPED_TRACE("mvox " + arguments);
  const auto before = tree_snapshot(directory);
  const CommandResult result = run_mvox(arguments, directory, prefix);
  expect_one_line_error(result, subject, exit_code);
  const std::string line = result.output.substr(0, result.output.find('\n'));
  EXPECT_EQ(line.rfind("mvox: error: " + subject, 0), 0u) << line;
  EXPECT_NE(line.find(problem, std::string("mvox: error: ").size() + subject.size()),
            std::string::npos)
      << "expected \"" << problem << "\" in: " << line;
  expect_same_tree(before, tree_snapshot(directory));
}

}  // namespace mvox::test
