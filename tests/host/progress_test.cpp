// The progress line: drawn only when enabled, first and last slice always drawn, and still
// redrawn after a pause that follows a burst of fast slices (it looks at the clock only every
// few slices when slices are fast).
#include "pipeline/progress.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace mvox {
namespace {

// What the body writes on standard error.
template <class Body>
std::string stderr_of(Body body) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("mvox_progress_test_" + std::to_string(::getpid())))
                               .string();
  std::fflush(stderr);
  const int saved = ::dup(STDERR_FILENO);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(fd, STDERR_FILENO);
  ::close(fd);
  body();
  std::fflush(stderr);
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  std::filesystem::remove(path);
  return text.str();
}

TEST(ProgressLine, DisabledWritesNothing) {
  EXPECT_EQ(stderr_of([] {
              ProgressLine progress("extracting", 1000, false);
              for (std::uint32_t done = 1; done <= 1000; ++done) progress.update(done);
            }),
            "");
}

TEST(ProgressLine, DrawsTheFirstAndTheLastSliceAndEndsTheLine) {
  const std::string text = stderr_of([] {
    ProgressLine progress("extracting", 1000000, true);
    for (std::uint32_t done = 1; done <= 1000000; ++done) progress.update(done);
  });
  EXPECT_EQ(text.rfind("\rextracting [", 0), 0u) << text.substr(0, 80);
  EXPECT_NE(text.find(" 1/1000000 slices"), std::string::npos);
  EXPECT_NE(text.find(" 1000000/1000000 slices"), std::string::npos);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  // Redrawn at most ten times a second, not once per slice.
  EXPECT_LT(std::count(text.begin(), text.end(), '\r'), 1000) << text.size();
}

TEST(ProgressLine, ARunThatSlowsDownAfterFastSlicesIsStillRedrawn) {
  constexpr std::uint32_t kFast = 1000000;
  const std::string text = stderr_of([] {
    ProgressLine progress("extracting", 0, true);
    for (std::uint32_t done = 1; done <= kFast; ++done) progress.update(done);
    // Longer than the 100 ms between redraws: the next look at the clock redraws, and it comes
    // within the largest stride, 1024 slices.
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    for (std::uint32_t done = kFast + 1; done <= kFast + 1025; ++done) progress.update(done);
  });
  const std::size_t last = text.rfind('\r');
  ASSERT_NE(last, std::string::npos);
  const std::uint32_t drawn = static_cast<std::uint32_t>(std::stoul(text.substr(last + 12)));
  EXPECT_GT(drawn, kFast) << text.substr(last);
}

}  // namespace
}  // namespace mvox
