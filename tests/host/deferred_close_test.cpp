// close_when_unneeded (src/write/deferred_close.h): inside an allowing DeferredCloses scope a
// large file is closed by a thread of its own, and closed for certain once the scope ends, by an
// exception too; a small file, any file in a scope that does not allow it (--threads 1), and any
// file outside every scope (the Python module's writers) is closed before the call returns.
#include "write/deferred_close.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>

namespace mvox {
namespace {

int open_scratch() {
  const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  EXPECT_GE(fd, 0);
  return fd;
}

bool is_open(int fd) { return ::fcntl(fd, F_GETFD) != -1 || errno != EBADF; }

TEST(DeferredClose, ALargeFileIsClosedByTheTimeTheScopeEnds) {
  int fd = -1;
  {
    const DeferredCloses scope(true);
    fd = open_scratch();
    close_when_unneeded(fd, kDeferredCloseBytes);
  }
  EXPECT_FALSE(is_open(fd));
}

TEST(DeferredClose, AScopeEndedByAnExceptionStillWaits) {
  int fd = -1;
  try {
    const DeferredCloses scope(true);
    fd = open_scratch();
    close_when_unneeded(fd, kDeferredCloseBytes);
    throw std::runtime_error("the run failed after its copy");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(is_open(fd));
}

TEST(DeferredClose, ASmallFileIsClosedAtOnce) {
  const DeferredCloses scope(true);
  const int fd = open_scratch();
  close_when_unneeded(fd, kDeferredCloseBytes - 1);
  EXPECT_FALSE(is_open(fd));
}

TEST(DeferredClose, WithOneThreadOrNoScopeEveryFileIsClosedAtOnce) {
  {
    const DeferredCloses scope(false);
    const int fd = open_scratch();
    close_when_unneeded(fd, kDeferredCloseBytes * 4);
    EXPECT_FALSE(is_open(fd));
  }
  const int fd = open_scratch();
  close_when_unneeded(fd, kDeferredCloseBytes * 4);
  EXPECT_FALSE(is_open(fd));
}

TEST(DeferredClose, ManyClosesAreAllFinished) {
  int fds[20];
  {
    const DeferredCloses scope(true);
    for (int& fd : fds) {
      fd = open_scratch();
      close_when_unneeded(fd, kDeferredCloseBytes);
    }
  }
  for (int fd : fds) EXPECT_FALSE(is_open(fd)) << fd;
}

}  // namespace
}  // namespace mvox
