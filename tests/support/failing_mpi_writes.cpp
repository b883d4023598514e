// A preload library for mvox-mpi's tests (LD_PRELOAD, passed to the ranks with mpirun -x): in the
// rank named by MVOX_FAIL_WRITES_RANK, the positioned writes MPI-IO makes (pwrite, pwritev and
// their 64-bit names) fail with ENOSPC, as on a full disk. MVOX_FAIL_WRITES=large fails those of
// 4 KiB or more (a rank's records), =small those below (rank 0's head). mvox's own files are
// written with write(), which passes.
#include <dlfcn.h>
#include <sys/types.h>
#include <sys/uio.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace {

// True, with errno set to ENOSPC, when this rank's write of `bytes` is to fail.
bool refused(std::size_t bytes) {
  const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
  const char* failing = std::getenv("MVOX_FAIL_WRITES_RANK");
  const char* which = std::getenv("MVOX_FAIL_WRITES");
  if (!rank || !failing || !which || std::strcmp(rank, failing) != 0) return false;
  const bool large = bytes >= 4096;
  if (std::strcmp(which, "large") == 0 ? !large : large) return false;
  errno = ENOSPC;
  return true;
}

std::size_t total(const struct iovec* pieces, int count) {
  std::size_t bytes = 0;
  for (int i = 0; i < count; ++i) bytes += pieces[i].iov_len;
  return bytes;
}

using Pwrite = ssize_t (*)(int, const void*, size_t, off_t);
using Pwritev = ssize_t (*)(int, const struct iovec*, int, off_t);

template <class Function>
Function next(const char* name) {
  return reinterpret_cast<Function>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

ssize_t pwrite(int fd, const void* data, size_t bytes, off_t at) {
  static const Pwrite real = next<Pwrite>("pwrite");
  return refused(bytes) ? -1 : real(fd, data, bytes, at);
}

ssize_t pwrite64(int fd, const void* data, size_t bytes, off_t at) {
  static const Pwrite real = next<Pwrite>("pwrite64");
  return refused(bytes) ? -1 : real(fd, data, bytes, at);
}

ssize_t pwritev(int fd, const struct iovec* pieces, int count, off_t at) {
  static const Pwritev real = next<Pwritev>("pwritev");
  return refused(total(pieces, count)) ? -1 : real(fd, pieces, count, at);
}

ssize_t pwritev64(int fd, const struct iovec* pieces, int count, off_t at) {
  static const Pwritev real = next<Pwritev>("pwritev64");
  return refused(total(pieces, count)) ? -1 : real(fd, pieces, count, at);
}

}  // extern "C"
