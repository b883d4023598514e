// Paths that name a descriptor (src/write/standard_descriptors.h): every spelling the header
// promises, and the names that only look close. Outputs named so are written through the
// descriptor; a wrong "no" would replace the shell's redirection target by a rename.
#include "write/standard_descriptors.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <optional>
#include <string>

namespace mvox {
namespace {

TEST(StandardDescriptors, EverySpellingOfADescriptorIsFound) {
  const std::string pid = std::to_string(::getpid());
  const struct {
    std::string path;
    std::optional<int> descriptor;
  } cases[] = {
      {"/dev/stdin", 0},
      {"/dev/stdout", 1},
      {"/dev/stderr", 2},
      {"/dev/fd/7", 7},
      {"/proc/self/fd/3", 3},
      {"/proc/thread-self/fd/4", 4},
      {"/proc/" + pid + "/fd/5", 5},
      {"/dev/./stdout", 1},
      {"/dev/fd/3/../4", 4},
      {"/tmp/../dev/stderr", 2},
      {"/dev//fd//6", 6},
      // Not descriptors: a name after them, their directories, other files.
      {"/dev/stdin/.", std::nullopt},
      {"/dev/fd/3/..", std::nullopt},
      {"/dev/fd/", std::nullopt},
      {"/dev/fd/x", std::nullopt},
      {"/dev/null", std::nullopt},
      {"/proc/1/fd/1", pid == "1" ? std::optional<int>(1) : std::nullopt},
      {"stdout", std::nullopt},
      {"scans/slice_0001.png", std::nullopt},
      {"3", std::nullopt},
      {"-", std::nullopt},
      {"", std::nullopt},
  };
  for (const auto& c : cases) EXPECT_EQ(descriptor_named_by(c.path), c.descriptor) << c.path;
}

}  // namespace
}  // namespace mvox
