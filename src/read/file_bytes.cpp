#include "read/file_bytes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "error.h"

namespace mvox {

void read_file_bytes(const std::string& path, ReadBuffer& bytes,
                     std::uint64_t max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error(path, "cannot open file: " + errno_text(errno));
  struct stat status {};
  const bool regular = ::fstat(fd, &status) == 0 && S_ISREG(status.st_mode);
  // One byte more than the size: the read that finds the end of the file needs room too.
  const std::uint64_t expected = regular ? static_cast<std::uint64_t>(status.st_size) + 1 : 65536;
  bytes.resize(static_cast<std::size_t>(std::min(expected, max_bytes)));
  std::size_t used = 0;
  while (used < max_bytes) {
    if (used == bytes.size())
      bytes.resize(static_cast<std::size_t>(std::min<std::uint64_t>(2 * bytes.size(), max_bytes)));
    const ssize_t got = ::read(fd, bytes.data() + used, bytes.size() - used);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const int error = errno;
      ::close(fd);
      throw Error(path, "read failed: " + errno_text(error));
    }
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
  }
  ::close(fd);
  bytes.resize(used);
}

}  // namespace mvox
