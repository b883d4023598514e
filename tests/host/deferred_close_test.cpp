// close_when_unneeded (src/write/deferred_close.h): a large file is closed by another thread,
// and closed for certain once finish_deferred_closes() returns; a small file, or any file when
// deferred closes are not allowed (--threads 1), is closed before the call returns.
#include "write/deferred_close.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>

namespace mvox {
namespace {

int open_scratch() {
  const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  EXPECT_GE(fd, 0);
  return fd;
}

bool is_open(int fd) { return ::fcntl(fd, F_GETFD) != -1 || errno != EBADF; }

TEST(DeferredClose, ALargeFileIsClosedByTheTimeTheRunFinishes) {
  allow_deferred_closes(true);
  const int fd = open_scratch();
  close_when_unneeded(fd, kDeferredCloseBytes);
  finish_deferred_closes();
  EXPECT_FALSE(is_open(fd));
}

TEST(DeferredClose, ASmallFileIsClosedAtOnce) {
  allow_deferred_closes(true);
  const int fd = open_scratch();
  close_when_unneeded(fd, kDeferredCloseBytes - 1);
  EXPECT_FALSE(is_open(fd));
  finish_deferred_closes();
}

TEST(DeferredClose, WithOneThreadEveryFileIsClosedAtOnce) {
  allow_deferred_closes(false);
  const int fd = open_scratch();
  close_when_unneeded(fd, kDeferredCloseBytes * 4);
  EXPECT_FALSE(is_open(fd));
  allow_deferred_closes(true);
}

TEST(DeferredClose, ManyClosesAreAllFinished) {
  allow_deferred_closes(true);
  int fds[20];
  for (int& fd : fds) {
    fd = open_scratch();
    close_when_unneeded(fd, kDeferredCloseBytes);
  }
  finish_deferred_closes();
  for (int fd : fds) EXPECT_FALSE(is_open(fd)) << fd;
}

}  // namespace
}  // namespace mvox
