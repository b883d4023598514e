#include "write/buffered_writer.h"

#include <unistd.h>

#include <algorithm>

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

int BufferedWriter::append_file(int from_fd, std::uint64_t size, bool* short_source) {
  *short_source = false;
  if (const int error = flush()) return error;
  loff_t from = 0;
  bool kernel_copies = true;
  while (size > 0) {
    const std::size_t want =
        static_cast<std::size_t>(std::min<std::uint64_t>(size, std::uint64_t{1} << 30));
    ssize_t got = -1;
    if (kernel_copies) {
      got = ::copy_file_range(from_fd, &from, fd_, nullptr, want, 0);
      if (got < 0 && errno == EINTR) continue;
      // Another file system, a pipe or device as the target, an old kernel: copy it ourselves.
      if (got < 0 && (errno == EXDEV || errno == EINVAL || errno == ENOSYS ||
                      errno == EOPNOTSUPP || errno == EBADF)) {
        kernel_copies = false;
        continue;
      }
      if (got < 0) return errno;
    } else {
      const std::size_t chunk = std::min(want, kBufferBytes);
      got = ::pread(from_fd, buffer_.get(), chunk, from);
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) return errno;
      if (got > 0) {
        if (const int error = write_fully(fd_, buffer_.get(), static_cast<std::size_t>(got)))
          return error;
        from += got;
      }
    }
    if (got == 0) {
      *short_source = true;
      return 0;
    }
    size -= static_cast<std::uint64_t>(got);
    total_ += static_cast<std::uint64_t>(got);
  }
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
