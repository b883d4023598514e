#pragma once
// Decompresses a zlib or gzip stream stored in part of a file, a piece at a time, so that a
// compressed volume streams through a fixed 64 KiB input buffer (NRRD gzip, MetaImage zlib).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "read/raw_file.h"
#include "read/read_buffer.h"

namespace mvox {

class InflateReader {
 public:
  // The compressed bytes are [offset, end) of `file`; `file` must outlive the reader. zlib and
  // gzip are told apart by their headers; gzip files of several members (concatenated .gz)
  // are read as one stream. Throws mvox::Error if zlib cannot start (out of memory).
  InflateReader(RawFile& file, std::uint64_t offset, std::uint64_t end);
  ~InflateReader();
  InflateReader(const InflateReader&) = delete;
  InflateReader& operator=(const InflateReader&) = delete;

  // Fills bytes[0, count) with the next decompressed bytes. Throws mvox::Error naming the file
  // when the data are corrupt, or end before `count` bytes ("compressed data end after N
  // bytes, expected EXPECTED_TOTAL for WHAT").
  void read(void* bytes, std::size_t count, std::uint64_t expected_total, const std::string& what);

  // Decompresses and drops up to `count` bytes; returns how many there were (fewer only when
  // the stream ends). Throws mvox::Error when the data are corrupt.
  std::uint64_t discard(std::uint64_t count);

  // Decompressed bytes delivered or dropped so far.
  std::uint64_t position() const { return position_; }

 private:
  // Decompresses up to `count` bytes into `out`; returns how many, 0 at the end of the stream.
  std::size_t inflate_some(unsigned char* out, std::size_t count);
  bool refill();  // more compressed input; false at `end_`

  struct Stream;  // zlib's z_stream, kept out of this header
  RawFile& file_;
  std::unique_ptr<Stream> stream_;
  ReadBuffer input_;
  std::uint64_t next_input_offset_;
  std::uint64_t end_;
  std::uint64_t position_ = 0;
  bool finished_ = false;
};

// The uncompressed size modulo 2^32 that a single-member gzip stream occupying [offset, end) of
// `file` records in its last four bytes, or nothing when [offset, end) does not start like gzip.
// A cheap check that needs no decompression; the trailer of a truncated file is garbage, so a
// mismatch only means "look closer".
std::optional<std::uint32_t> gzip_trailer_size(RawFile& file, std::uint64_t offset,
                                               std::uint64_t end);

}  // namespace mvox
