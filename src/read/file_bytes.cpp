#include "read/file_bytes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <limits>

#include "error.h"

namespace mvox {

namespace {

struct OpenDescriptor {
  int fd;
  ~OpenDescriptor() { ::close(fd); }
};

[[noreturn]] void refuse_beyond(const std::string& path, std::uint64_t most) {
  throw Error(path,
              "holds more than its header describes (at most " + std::to_string(most) + " bytes)");
}

}  // namespace

void read_file_bytes(const std::string& path, ReadBuffer& bytes, std::uint64_t max_bytes,
                     FileKinds kinds, const StartCheck& start) {
  // O_NONBLOCK: opening a FIFO does not wait for a writer; a regular file reads as without.
  const bool only_regular = kinds == FileKinds::only_regular;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (only_regular ? O_NONBLOCK : 0));
  if (fd < 0) throw Error(path, "cannot open file: " + errno_text(errno));
  const OpenDescriptor file{fd};
  struct stat status {};
  const bool regular = ::fstat(fd, &status) == 0 && S_ISREG(status.st_mode);
  if (only_regular && !regular)
    throw Error(path, "is no longer a regular file");
  // One byte more than the size: the read that finds the end of the file needs room too.
  const std::uint64_t expected =
      std::min(regular ? static_cast<std::uint64_t>(status.st_size) + 1 : 65536, max_bytes);
  // With a check of the start, room for the start first: the rest may be endless, or more than
  // memory holds, and is read only once the start is this format's.
  bool checked = !start.check;
  bytes.resize(static_cast<std::size_t>(
      checked ? expected
              : std::min<std::uint64_t>(expected, std::max<std::size_t>(start.bytes, 1))));
  std::size_t used = 0;
  std::uint64_t most = std::numeric_limits<std::uint64_t>::max();  // what the start allows
  const auto check_start = [&] {
    most = start.check(bytes.data(), used);
    checked = true;
    if (regular && static_cast<std::uint64_t>(status.st_size) > most) refuse_beyond(path, most);
    // One byte more than it allows: a stream that holds more is found so.
    if (most < max_bytes) max_bytes = most + 1;
  };
  for (;;) {
    if (!checked && used >= start.bytes) {
      check_start();
      if (expected > bytes.size())
        bytes.resize(static_cast<std::size_t>(std::min(expected, max_bytes)));
    }
    if (used >= max_bytes) break;  // the check may have lowered it below what was read
    if (used == bytes.size())
      bytes.resize(static_cast<std::size_t>(std::min<std::uint64_t>(2 * bytes.size(), max_bytes)));
    const ssize_t got = ::read(fd, bytes.data() + used, bytes.size() - used);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw Error(path, "read failed: " + errno_text(errno));
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
  }
  if (!checked) check_start();
  if (used > most) refuse_beyond(path, most);
  bytes.resize(used);
}

}  // namespace mvox
