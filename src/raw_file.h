#pragma once
// A file of headerless samples, read at byte offsets; shared by the two raw slice readers.
#include <cstddef>
#include <cstdint>
#include <string>

namespace mvox {

// Owns an open file descriptor (closed on destruction). Every error is an mvox::Error naming
// the file.
//
// A file that is not a regular file (a pipe, a FIFO, /dev/stdin) is a stream: its size is not
// known in advance, so expect_size() accepts it, its bytes must be read in order, and
// expect_end() checks at the end that nothing follows. Opening a FIFO waits for its writer.
class RawFile {
 public:
  explicit RawFile(const std::string& path);
  ~RawFile();
  RawFile(const RawFile&) = delete;
  RawFile& operator=(const RawFile&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t size_bytes() const { return size_bytes_; }

  // True for pipes and FIFOs: sizes are checked as the bytes arrive.
  bool is_stream() const { return is_stream_; }

  // Throws unless the file holds exactly `expected_bytes`; `what` says what they are for,
  // e.g. "one 256x256 u16be slice". A stream passes (see expect_end).
  void expect_size(std::uint64_t expected_bytes, const std::string& what) const;

  // Reads exactly `byte_count` bytes starting at `offset` into `bytes`. On a stream `offset`
  // must be where the previous read ended.
  void read_at(std::uint64_t offset, void* bytes, std::size_t byte_count);

  // After the last expected byte (`expected_bytes` in all) has been read: throws if a stream
  // holds more. Regular files were checked by expect_size.
  void expect_end(std::uint64_t expected_bytes, const std::string& what);

 private:
  std::string path_;
  int descriptor_ = -1;
  std::uint64_t size_bytes_ = 0;
  bool is_stream_ = false;
  std::uint64_t stream_position_ = 0;  // bytes read so far from a stream
};

// The message a wrong-sized raw file gets: "file is N bytes, expected M for WHAT".
std::string raw_size_problem(std::uint64_t actual_bytes, std::uint64_t expected_bytes,
                             const std::string& what);

}  // namespace mvox
