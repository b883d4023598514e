#include "read/inflate_reader.h"

#include <zlib.h>

#include <algorithm>
#include <limits>

#include "error.h"

namespace mvox {
namespace {

constexpr std::size_t kInputBytes = 64 * 1024;
// zlib counts in 32-bit uInt; larger requests are served in pieces of this size.
constexpr std::size_t kMaxPieceBytes = std::size_t{1} << 30;
// windowBits 15 (the largest window) + 32: let zlib detect a zlib or a gzip header itself.
constexpr int kDetectZlibOrGzip = 15 + 32;

}  // namespace

struct InflateReader::Stream {
  z_stream z{};
};

InflateReader::InflateReader(RawFile& file, std::uint64_t offset, std::uint64_t end)
    : file_(file),
      stream_(std::make_unique<Stream>()),
      input_(kInputBytes),
      next_input_offset_(offset),
      end_(end) {
  if (inflateInit2(&stream_->z, kDetectZlibOrGzip) != Z_OK) {
    throw Error(file_.name(), "cannot start zlib decompression (out of memory)");
  }
}

InflateReader::~InflateReader() { inflateEnd(&stream_->z); }

bool InflateReader::refill() {
  if (next_input_offset_ >= end_) return false;
  const std::size_t count =
      static_cast<std::size_t>(std::min<std::uint64_t>(input_.size(), end_ - next_input_offset_));
  file_.read_at(next_input_offset_, input_.data(), count);
  next_input_offset_ += count;
  stream_->z.next_in = input_.data();
  stream_->z.avail_in = static_cast<uInt>(count);
  return true;
}

std::size_t InflateReader::inflate_some(unsigned char* out, std::size_t count) {
  z_stream& z = stream_->z;
  if (finished_ || count == 0) return 0;
  z.next_out = out;
  z.avail_out = static_cast<uInt>(std::min(count, kMaxPieceBytes));
  const uInt asked = z.avail_out;
  while (z.avail_out > 0) {
    // Out of input with room left for output: everything the input held has come out, so the
    // stream was cut short; the caller reports how many bytes it got.
    if (z.avail_in == 0 && !refill()) {
      finished_ = true;
      break;
    }
    const int status = inflate(&z, Z_NO_FLUSH);
    if (status == Z_OK || status == Z_BUF_ERROR) continue;
    if (status == Z_STREAM_END) {
      // Another gzip member may follow (concatenated .gz files are one stream to gunzip);
      // anything else after the end, such as a final newline, is ignored.
      if (z.avail_in == 0) refill();
      if (z.avail_in >= 2 && z.next_in[0] == 0x1f && z.next_in[1] == 0x8b) {
        inflateReset(&z);
        continue;
      }
      finished_ = true;
      break;
    }
    const std::string detail = z.msg ? z.msg : ("zlib error " + std::to_string(status));
    if (status == Z_MEM_ERROR) throw Error(file_.name(), "out of memory while decompressing");
    throw Error(file_.name(), "compressed data are corrupt after " +
                                  std::to_string(position_ + (asked - z.avail_out)) +
                                  " decompressed bytes (zlib: " + detail + ")");
  }
  const std::size_t produced = asked - z.avail_out;
  position_ += produced;
  return produced;
}

void InflateReader::read(void* bytes, std::size_t count, std::uint64_t expected_total,
                         const std::string& what) {
  auto* out = static_cast<unsigned char*>(bytes);
  std::size_t done = 0;
  while (done < count) {
    const std::size_t got = inflate_some(out + done, count - done);
    if (got == 0) {
      throw Error(file_.name(), "compressed data end after " + std::to_string(position_) +
                                    " bytes, expected " + std::to_string(expected_total) + " for " +
                                    what);
    }
    done += got;
  }
}

std::uint64_t InflateReader::discard(std::uint64_t count) {
  std::vector<unsigned char> scratch(
      static_cast<std::size_t>(std::min<std::uint64_t>(count, kInputBytes)));
  std::uint64_t done = 0;
  while (done < count) {
    const std::size_t got = inflate_some(
        scratch.data(),
        static_cast<std::size_t>(std::min<std::uint64_t>(count - done, scratch.size())));
    if (got == 0) break;
    done += got;
  }
  return done;
}

std::optional<std::uint32_t> gzip_trailer_size(RawFile& file, std::uint64_t offset,
                                               std::uint64_t end) {
  constexpr std::uint64_t kSmallestGzip = 18;  // 10-byte header, empty deflate, 8-byte trailer
  if (end < offset || end - offset < kSmallestGzip) return std::nullopt;
  unsigned char magic[2];
  file.read_at(offset, magic, 2);
  if (magic[0] != 0x1f || magic[1] != 0x8b) return std::nullopt;
  unsigned char trailer[4];
  file.read_at(end - 4, trailer, 4);
  // ISIZE is little-endian whatever the machine (RFC 1952).
  return static_cast<std::uint32_t>(trailer[0] | (trailer[1] << 8) | (trailer[2] << 16) |
                                    (static_cast<std::uint32_t>(trailer[3]) << 24));
}

}  // namespace mvox
