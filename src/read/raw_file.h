#pragma once
// A file of headerless samples, read at byte offsets; shared by the two raw slice readers.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "read/file_kinds.h"
#include "read/read_buffer.h"

namespace mvox {

// Owns an open file descriptor (closed on destruction). Every error is an mvox::Error naming
// the file (name()).
//
// A file that is not a regular file (a pipe, a FIFO, /dev/stdin) is a stream: its size is not
// known in advance, so expect_size() accepts it, its bytes must be read in order, and
// expect_end() checks at the end that nothing follows. Opening a FIFO waits for its writer.
class RawFile {
 public:
  // `kind` names what the file should be, for the refusal of a directory. `same_file_as`: the
  // file opened again, by the same path, for a reader of its own (a slab's): refused unless the
  // path still names that file, so that a run never mixes two files, nor waits for the writer
  // of a FIFO put in the file's place. `kinds` only_regular: a file listed as a regular file
  // and opened at its turn (a raw slice, a TIFF file of a stack), refused with "is no longer a
  // regular file" when it is not one now, without waiting for a FIFO's writer (file_bytes.h).
  explicit RawFile(const std::string& path, const char* kind = "a raw sample file",
                   const RawFile* same_file_as = nullptr, FileKinds kinds = FileKinds::any);
  ~RawFile();
  RawFile(const RawFile&) = delete;
  RawFile& operator=(const RawFile&) = delete;

  const std::string& path() const { return path_; }
  // How messages name it: the path, or "standard input" for /dev/stdin (input_name).
  const std::string& name() const { return name_; }
  std::uint64_t size_bytes() const { return size_bytes_; }

  // True for pipes and FIFOs: sizes are checked as the bytes arrive.
  bool is_stream() const { return is_stream_; }

  // Throws unless the file holds exactly `expected_bytes`; `what` says what they are for,
  // e.g. "one 256x256 u16be slice". A stream passes (see expect_end), and a read that finds it
  // ended early then names the size expected and what for, as a file's size is named here.
  void expect_size(std::uint64_t expected_bytes, const std::string& what);

  // Reads exactly `byte_count` bytes starting at `offset` into `bytes`. On a stream `offset`
  // must be where the previous read ended.
  void read_at(std::uint64_t offset, void* bytes, std::size_t byte_count) {
    read_some(offset, bytes, byte_count, byte_count);
  }

  // Reads at least `min_count` and at most `max_count` bytes starting at `offset` into `bytes`,
  // and returns how many: as many as one read gives once `min_count` have arrived, so a stream
  // never waits for more than `min_count`. Fails as read_at does when the file ends before
  // `min_count`.
  std::size_t read_some(std::uint64_t offset, void* bytes, std::size_t min_count,
                        std::size_t max_count);

  // After the last expected byte (`expected_bytes` in all) has been read: throws if a stream
  // holds more. Regular files were checked by expect_size.
  void expect_end(std::uint64_t expected_bytes, const std::string& what);

 private:
  std::string path_;
  std::string name_;
  int descriptor_ = -1;
  std::uint64_t device_ = 0, inode_ = 0;  // which file it is (fstat)
  std::uint64_t size_bytes_ = 0;
  bool is_stream_ = false;
  std::uint64_t stream_position_ = 0;  // bytes read so far from a stream
  std::string stream_expected_;        // " bytes, expected N for WHAT", from expect_size
};

// Consecutive slices of `slice_bytes` each, from byte `offset` of a file on, read a chunk of
// several at a time: one system call per chunk instead of one per slice, which for slices of a
// few bytes costs far more than the slices themselves. A chunk is as many whole slices as fit in
// `chunk_bytes`, at least one, so the memory is max(chunk_bytes, slice_bytes), whatever the
// number of slices. A stream is read as it arrives: next() waits only for the slice it returns,
// so an error (a pipe that ends early) comes at the slice where it happens, as with one read
// per slice, and a pipe that trickles is not held back.
class ChunkedSliceReader {
 public:
  ChunkedSliceReader(RawFile& file, std::uint64_t offset, std::size_t slice_bytes,
                     std::uint64_t slice_count, std::size_t chunk_bytes);

  // The next slice's bytes, which the caller may change in place; valid until the next call.
  // At most `slice_count` calls.
  unsigned char* next();

  // The memory next() allocates with the first slice: max(chunk_bytes, slice_bytes).
  std::size_t buffer_bytes() const { return buffer_bytes_; }

 private:
  RawFile& file_;
  std::size_t slice_bytes_;
  std::uint64_t next_offset_;  // in the file: the first byte not yet read
  std::uint64_t end_offset_;   // in the file: one past the last slice's last byte
  std::size_t buffer_bytes_ = 0;
  ReadBuffer buffer_;
  std::size_t begin_ = 0;  // in buffer_: the next slice's first byte
  std::size_t end_ = 0;    // in buffer_: one past the last byte read
};

// The message a wrong-sized raw file gets: "file is N bytes, expected M for WHAT".
std::string raw_size_problem(std::uint64_t actual_bytes, std::uint64_t expected_bytes,
                             const std::string& what);

}  // namespace mvox
