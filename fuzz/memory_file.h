#pragma once
// For fuzz targets whose code under test opens a path: an in-memory file (memfd), named by its
// /proc/self/fd path and rewritten for every input, so no disk traffic and nothing left behind.
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.h"

namespace mvox::fuzz {

// The path of the one in-memory file, now holding exactly `size` bytes from `bytes`.
inline const std::string& memory_file_with(const std::uint8_t* bytes, std::size_t size) {
  static const int fd = ::memfd_create("mvox_fuzz_input", 0);
  static const std::string path = "/proc/self/fd/" + std::to_string(fd);
  MVOX_FUZZ_CHECK(fd >= 0 && ::ftruncate(fd, 0) == 0, "memfd");
  std::size_t done = 0;
  while (done < size) {
    const ssize_t put = ::pwrite(fd, bytes + done, size - done, static_cast<off_t>(done));
    MVOX_FUZZ_CHECK(put > 0, "pwrite");
    done += static_cast<std::size_t>(put);
  }
  return path;
}

}  // namespace mvox::fuzz
