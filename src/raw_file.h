#pragma once
// A file of headerless samples, read at byte offsets; shared by the two raw slice readers.
#include <cstddef>
#include <cstdint>
#include <string>

namespace mvox {

// Owns an open file descriptor (closed on destruction). Every error is an mvox::Error naming
// the file.
class RawFile {
 public:
  explicit RawFile(const std::string& path);
  ~RawFile();
  RawFile(const RawFile&) = delete;
  RawFile& operator=(const RawFile&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t size_bytes() const { return size_bytes_; }

  // Throws unless the file holds exactly `expected_bytes`; `what` says what they are for,
  // e.g. "one 256x256 u16be slice".
  void expect_size(std::uint64_t expected_bytes, const std::string& what) const;

  // Reads exactly `byte_count` bytes starting at `offset` into `bytes`.
  void read_at(std::uint64_t offset, void* bytes, std::size_t byte_count) const;

 private:
  std::string path_;
  int descriptor_ = -1;
  std::uint64_t size_bytes_ = 0;
};

// The message a wrong-sized raw file gets: "file is N bytes, expected M for WHAT".
std::string raw_size_problem(std::uint64_t actual_bytes, std::uint64_t expected_bytes,
                             const std::string& what);

}  // namespace mvox
