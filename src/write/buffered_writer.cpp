#include "write/buffered_writer.h"

#include <unistd.h>

#include <cerrno>

namespace mvox {

BufferedWriter::BufferedWriter() : buffer_(new char[kBufferBytes]) {}

int BufferedWriter::flush() {
  if (used_ == 0) return 0;
  const int error = write_fully(fd_, buffer_.get(), used_);
  // Drop the bytes even after an error: the owner reports it and stops writing this file.
  used_ = 0;
  return error;
}

int BufferedWriter::write_slow(const void* data, std::size_t size) {
  if (const int error = flush()) return error;
  if (size < kBufferBytes) {
    std::memcpy(buffer_.get(), data, size);
    used_ = size;
    total_ += size;
    return 0;
  }
  // A block at least as large as the buffer gains nothing from a copy.
  if (const int error = write_fully(fd_, data, size)) return error;
  total_ += size;
  return 0;
}

int write_fully(int fd, const void* data, std::size_t size) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t written = ::write(fd, bytes, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    // write(2) returning 0 for a non-empty request means the device takes no more.
    if (written == 0) return ENOSPC;
    bytes += written;
    size -= static_cast<std::size_t>(written);
  }
  return 0;
}

}  // namespace mvox
