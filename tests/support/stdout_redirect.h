#pragma once
// Test support: send what a writer puts on standard output into a file.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace mvox::test {

// Points file descriptor 1 at `path` for the lifetime of the object.
class StdoutRedirect {
 public:
  explicit StdoutRedirect(const std::string& path) {
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, STDOUT_FILENO);
    ::close(fd);
  }
  ~StdoutRedirect() {
    std::fflush(stdout);
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
  }
  StdoutRedirect(const StdoutRedirect&) = delete;
  StdoutRedirect& operator=(const StdoutRedirect&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace mvox::test
