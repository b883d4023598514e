#pragma once
// Test support: "refused, and nothing lost". A command mvox must refuse is run in a directory,
// and the test checks the whole contract of README's "When things go wrong": one line starting
// "mvox: error: SUBJECT" that says PROBLEM, the exit code, and every file under the directory
// (inputs, previous outputs, everything) byte for byte as it was, with nothing added.
#include <filesystem>
#include <map>
#include <string>

namespace mvox::test {

// Every entry under `root`, recursively and hidden ones included: its path relative to `root`,
// mapped to what it is: "file:" and its bytes, "link:" and its target, or "directory". Files
// over 64 MiB (a sparse file standing for a huge scan) are "large file:" with their size and
// modification time instead of their bytes.
std::map<std::string, std::string> tree_snapshot(const std::filesystem::path& root);

// Adds a test failure for each entry added, removed or changed between two snapshots.
void expect_same_tree(const std::map<std::string, std::string>& before,
                      const std::map<std::string, std::string>& after);

// Runs `mvox ARGUMENTS` from `directory` (through the shell, after `prefix`) and checks the
// contract above. `problem` must appear in the line after the subject.
void expect_refused(const std::filesystem::path& directory, const std::string& arguments,
                    const std::string& subject, const std::string& problem, int exit_code = 1,
                    const std::string& prefix = "");

}  // namespace mvox::test
