#include "raw_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include "error.h"

namespace mvox {

RawFile::RawFile(const std::string& path) : path_(path) {
  descriptor_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor_ < 0) throw Error(path, "cannot open: " + errno_text(errno));
  struct stat status {};
  if (::fstat(descriptor_, &status) != 0) {
    const int error_number = errno;
    ::close(descriptor_);
    throw Error(path, "cannot get file size: " + errno_text(error_number));
  }
  if (S_ISDIR(status.st_mode)) {
    ::close(descriptor_);
    throw Error(path, "is a directory, expected a raw sample file");
  }
  size_bytes_ = static_cast<std::uint64_t>(status.st_size);
}

RawFile::~RawFile() {
  if (descriptor_ >= 0) ::close(descriptor_);
}

void RawFile::expect_size(std::uint64_t expected_bytes, const std::string& what) const {
  if (size_bytes_ != expected_bytes) {
    throw Error(path_, raw_size_problem(size_bytes_, expected_bytes, what));
  }
}

void RawFile::read_at(std::uint64_t offset, void* bytes, std::size_t byte_count) const {
  auto* destination = static_cast<char*>(bytes);
  std::size_t done = 0;
  // pread may return fewer bytes than asked (large requests, signals), so loop until done.
  while (done < byte_count) {
    const ssize_t got = ::pread(descriptor_, destination + done, byte_count - done,
                                static_cast<off_t>(offset + done));
    if (got < 0) {
      if (errno == EINTR) continue;
      throw Error(path_, "read failed: " + errno_text(errno));
    }
    if (got == 0) {
      throw Error(path_, "file ended at byte " + std::to_string(offset + done) + ", expected " +
                             std::to_string(offset + byte_count) + " bytes");
    }
    done += static_cast<std::size_t>(got);
  }
}

std::string raw_size_problem(std::uint64_t actual_bytes, std::uint64_t expected_bytes,
                             const std::string& what) {
  return "file is " + std::to_string(actual_bytes) + " bytes, expected " +
         std::to_string(expected_bytes) + " for " + what;
}

}  // namespace mvox
