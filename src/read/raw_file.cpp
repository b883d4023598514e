#include "read/raw_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "error.h"
#include "read/buffer_allocation.h"
#include "read/input_name.h"
#include "read/read_cancellation.h"

namespace mvox {

RawFile::RawFile(const std::string& path, const char* kind, const RawFile* same_file_as,
                 FileKinds kinds)
    : path_(path), name_(input_name(path)) {
  // Opening a FIFO waits for its writer: wanted for a volume piped in, never when the file is
  // opened again for a slab, or opened at its turn after it was listed (it was a file then,
  // and a FIFO now has no writer coming).
  const bool only_regular = kinds == FileKinds::only_regular;
  const bool no_wait = same_file_as || only_regular;
  descriptor_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (no_wait ? O_NONBLOCK : 0));
  if (descriptor_ < 0) throw Error(name_, "cannot open: " + errno_text(errno));
  struct stat status {};
  if (::fstat(descriptor_, &status) != 0) {
    const int error_number = errno;
    ::close(descriptor_);
    throw Error(name_, "cannot get file size: " + errno_text(error_number));
  }
  device_ = static_cast<std::uint64_t>(status.st_dev);
  inode_ = static_cast<std::uint64_t>(status.st_ino);
  if (same_file_as && (device_ != same_file_as->device_ || inode_ != same_file_as->inode_)) {
    ::close(descriptor_);
    throw Error(name_, "was replaced by another file while mvox read it; nothing was written");
  }
  if (only_regular && !S_ISREG(status.st_mode)) {
    ::close(descriptor_);
    throw Error(name_, "is no longer a regular file");
  }
  // O_NONBLOCK changes nothing for a regular file's reads; anything else reads waiting again.
  if (no_wait && !S_ISREG(status.st_mode)) {
    const int flags = ::fcntl(descriptor_, F_GETFL);
    if (flags < 0 || ::fcntl(descriptor_, F_SETFL, flags & ~O_NONBLOCK) != 0) {
      const int error_number = errno;
      ::close(descriptor_);
      throw Error(name_, "cannot open: " + errno_text(error_number));
    }
  }
  if (S_ISDIR(status.st_mode)) {
    ::close(descriptor_);
    throw Error(name_, std::string("is a directory, expected ") + kind);
  }
  is_stream_ = !S_ISREG(status.st_mode);
  size_bytes_ = is_stream_ ? 0 : static_cast<std::uint64_t>(status.st_size);
}

RawFile::~RawFile() {
  if (descriptor_ >= 0) ::close(descriptor_);
}

void RawFile::expect_size(std::uint64_t expected_bytes, const std::string& what) {
  if (is_stream_) {
    stream_expected_ = " bytes, expected " + std::to_string(expected_bytes) + " for " + what;
    return;
  }
  if (size_bytes_ != expected_bytes)
    throw Error(name_, raw_size_problem(size_bytes_, expected_bytes, what));
}

std::size_t RawFile::read_some(std::uint64_t offset, void* bytes, std::size_t min_count,
                               std::size_t max_count) {
  if (is_stream_ && offset != stream_position_)
    throw Error(name_, "cannot seek in a pipe: reading byte " + std::to_string(offset) +
                           " after byte " + std::to_string(stream_position_));
  auto* destination = static_cast<char*>(bytes);
  std::size_t done = 0;
  // pread and read may return fewer bytes than asked (large requests, signals, a pipe that has
  // only part of the data yet), so loop until enough.
  while (done < min_count) {
    const ssize_t got = is_stream_ ? ::read(descriptor_, destination + done, max_count - done)
                                   : ::pread(descriptor_, destination + done, max_count - done,
                                             static_cast<off_t>(offset + done));
    if (got < 0) {
      if (errno == EINTR && reads_cancelled()) throw Error(name_, "reading stopped");
      if (errno == EINTR) continue;
      throw Error(name_, "read failed: " + errno_text(errno));
    }
    if (got == 0 && is_stream_ && !stream_expected_.empty())
      throw Error(name_, "ended after " + std::to_string(offset + done) + stream_expected_);
    if (got == 0) {
      throw Error(name_, "file ended at byte " + std::to_string(offset + done) + ", expected " +
                             std::to_string(offset + min_count) + " bytes");
    }
    done += static_cast<std::size_t>(got);
    if (is_stream_) stream_position_ += static_cast<std::uint64_t>(got);
  }
  return done;
}

void RawFile::expect_end(std::uint64_t expected_bytes, const std::string& what) {
  if (!is_stream_) return;
  char extra = 0;
  ssize_t got;
  do {
    got = ::read(descriptor_, &extra, 1);
  } while (got < 0 && errno == EINTR && !reads_cancelled());
  if (got < 0) throw Error(name_, "read failed: " + errno_text(errno));
  if (got > 0)
    throw Error(name_, "holds more than the " + std::to_string(expected_bytes) +
                           " bytes expected for " + what);
}

ChunkedSliceReader::ChunkedSliceReader(RawFile& file, std::uint64_t offset, std::size_t slice_bytes,
                                       std::uint64_t slice_count, std::size_t chunk_bytes)
    : file_(file),
      slice_bytes_(slice_bytes),
      next_offset_(offset),
      end_offset_(offset + slice_count * slice_bytes) {
  const std::size_t slices = slice_bytes == 0 ? 1 : chunk_bytes / slice_bytes;
  buffer_bytes_ = (slices > 0 ? slices : 1) * slice_bytes;
}

unsigned char* ChunkedSliceReader::next() {
  // Allocated with the first slice, not by the constructor: a run's memory plan may refuse it.
  if (buffer_.empty()) resize_buffer(buffer_, buffer_bytes_, file_.name(), "slices");
  if (end_ - begin_ < slice_bytes_) {
    // A stream may have delivered part of a slice: it moves to the front, and the read
    // completes it.
    const std::size_t part = end_ - begin_;
    if (part > 0) std::memmove(buffer_.data(), buffer_.data() + begin_, part);
    begin_ = 0;
    end_ = part;
    // Never past the last slice: what follows it is for the caller to check (expect_end).
    const std::uint64_t room = buffer_.size() - part;
    const std::size_t wanted =
        static_cast<std::size_t>(std::min<std::uint64_t>(room, end_offset_ - next_offset_));
    const std::size_t got =
        file_.read_some(next_offset_, buffer_.data() + part, slice_bytes_ - part, wanted);
    end_ += got;
    next_offset_ += got;
  }
  unsigned char* slice = buffer_.data() + begin_;
  begin_ += slice_bytes_;
  return slice;
}

std::string raw_size_problem(std::uint64_t actual_bytes, std::uint64_t expected_bytes,
                             const std::string& what) {
  return "file is " + std::to_string(actual_bytes) + " bytes, expected " +
         std::to_string(expected_bytes) + " for " + what;
}

}  // namespace mvox
