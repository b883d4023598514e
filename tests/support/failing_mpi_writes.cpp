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

bool fails(std::size_t bytes) {
  const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
  const char* failing = std::getenv("MVOX_FAIL_WRITES_RANK");
  const char* which = std::getenv("MVOX_FAIL_WRITES");
  if (!rank || !failing || !which || std::strcmp(rank, failing) != 0) return false;
  const bool large = bytes >= 4096;
  return std::strcmp(which, "large") == 0 ? large : !large;
}

std::size_t total(const struct iovec* pieces, int count) {
  std::size_t bytes = 0;
  for (int i = 0; i < count; ++i) bytes += pieces[i].iov_len;
  return bytes;
}

template <class Function>
Function next(const char* name) {
  return reinterpret_cast<Function>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

ssize_t pwrite(int fd, const void* data, size_t bytes, off_t at) {
  if (fails(bytes)) {
    errno = ENOSPC;
    return -1;
  }
  static const auto real = next<ssize_t (*)(int, const void*, size_t, off_t)>("pwrite");
  return real(fd, data, bytes, at);
}

ssize_t pwrite64(int fd, const void* data, size_t bytes, off_t at) {
  if (fails(bytes)) {
    errno = ENOSPC;
    return -1;
  }
  static const auto real = next<ssize_t (*)(int, const void*, size_t, off_t)>("pwrite64");
  return real(fd, data, bytes, at);
}

ssize_t pwritev(int fd, const struct iovec* pieces, int count, off_t at) {
  if (fails(total(pieces, count))) {
    errno = ENOSPC;
    return -1;
  }
  static const auto real = next<ssize_t (*)(int, const struct iovec*, int, off_t)>("pwritev");
  return real(fd, pieces, count, at);
}

ssize_t pwritev64(int fd, const struct iovec* pieces, int count, off_t at) {
  if (fails(total(pieces, count))) {
    errno = ENOSPC;
    return -1;
  }
  static const auto real = next<ssize_t (*)(int, const struct iovec*, int, off_t)>("pwritev64");
  return real(fd, pieces, count, at);
}

}  // extern "C"
