#include "write/standard_descriptors.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace mvox {
namespace {

bool g_closed[3] = {false, false, false};

// N when `text` is a decimal descriptor number that fits an int, else -1.
int descriptor_number(const std::string& text) {
  if (text.empty() || text.size() > 9) return -1;
  for (const char c : text)
    if (c < '0' || c > '9') return -1;
  return std::atoi(text.c_str());
}

}  // namespace

void secure_standard_descriptors() {
  static bool done = false;
  if (done) return;
  done = true;
  for (int fd = 0; fd <= 2; ++fd) {
    if (::fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
    g_closed[fd] = true;
    // open() returns the lowest free descriptor, which is this one: the lower ones are open.
    const int opened = ::open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY);
    if (opened >= 0 && opened != fd) {
      ::dup2(opened, fd);
      ::close(opened);
    }
  }
}

bool standard_descriptor_was_closed(int fd) { return fd >= 0 && fd <= 2 && g_closed[fd]; }

std::optional<int> descriptor_named_by(const std::string& path) {
  if (path.empty() || path == "-") return std::nullopt;
  // Only a last component that names a descriptor ("stdin", "3") can survive normalizing below
  // as one ("x/.." and "x/." end in a directory). Most paths are slices of a stack, thousands of
  // them, and are let go here, before the path is made absolute and split.
  const std::string last = path.substr(path.rfind('/') + 1);
  if (last != "stdin" && last != "stdout" && last != "stderr" && descriptor_number(last) < 0 &&
      last != "." && last != ".." && !last.empty())
    return std::nullopt;
  std::error_code error;
  std::filesystem::path absolute = std::filesystem::absolute(path, error);
  if (error) return std::nullopt;
  absolute = absolute.lexically_normal();
  const std::string name = absolute.filename().string();
  const std::string directory = absolute.parent_path().string();
  if (directory == "/dev") {
    if (name == "stdin") return 0;
    if (name == "stdout") return 1;
    if (name == "stderr") return 2;
    return std::nullopt;
  }
  const int number = descriptor_number(name);
  if (number < 0) return std::nullopt;
  if (directory == "/dev/fd" || directory == "/proc/self/fd" ||
      directory == "/proc/thread-self/fd" ||
      directory == "/proc/" + std::to_string(::getpid()) + "/fd")
    return number;
  return std::nullopt;
}

std::string descriptor_name(int fd) {
  switch (fd) {
    case 0: return "standard input";
    case 1: return "standard output";
    case 2: return "standard error";
    default: return "descriptor " + std::to_string(fd);
  }
}

}  // namespace mvox
