#include "read/zlib_stream_check.h"

#include <zlib.h>

#include <algorithm>
#include <new>

namespace mvox {

struct ZlibStreamCheck::Stream {
  z_stream z{};
  ~Stream() { inflateEnd(&z); }
};

ZlibStreamCheck::ZlibStreamCheck() = default;
ZlibStreamCheck::~ZlibStreamCheck() = default;

ZlibStreamCheck::Result ZlibStreamCheck::inflate(const unsigned char* bytes, std::size_t size,
                                                 unsigned char* out, std::size_t out_bytes) {
  if (!stream_) {
    auto stream = std::make_unique<Stream>();
    // Only Z_MEM_ERROR is possible here (the version and parameters are right).
    if (inflateInit(&stream->z) != Z_OK) throw std::bad_alloc();
    stream_ = std::move(stream);
    scratch_.resize(32 * 1024);
  } else if (inflateReset(&stream_->z) != Z_OK) {
    return {"zlib cannot restart", 0};
  }
  z_stream& z = stream_->z;
  // inflateReset keeps the counts the last stream left: a stream that ended before its stored
  // bytes did, or inflated past the caller's bytes into the scratch buffer, would hand this one
  // its leftover counts with the new pointers (a read past `bytes`, a write past `out`).
  z.next_in = const_cast<unsigned char*>(bytes);  // zlib's API is not const, but only reads
  z.avail_in = 0;
  z.next_out = out;
  z.avail_out = 0;
  std::size_t in_left = size;
  std::size_t out_left = out_bytes;
  Result result;
  for (;;) {
    // zlib counts in uInt: very large strips go in pieces.
    if (z.avail_in == 0 && in_left > 0) {
      z.avail_in = static_cast<uInt>(std::min<std::size_t>(in_left, 1u << 30));
      in_left -= z.avail_in;
    }
    if (z.avail_out == 0) {
      if (out_left > 0) {
        z.avail_out = static_cast<uInt>(std::min<std::size_t>(out_left, 1u << 30));
        out_left -= z.avail_out;
      } else {  // past the caller's bytes: what is left is inflated only to reach the check
        z.next_out = scratch_.data();
        z.avail_out = static_cast<uInt>(scratch_.size());
      }
    }
    const uInt space = z.avail_out;
    const int status = ::inflate(&z, Z_NO_FLUSH);
    result.total += space - z.avail_out;
    if (status == Z_STREAM_END) return result;
    if (status == Z_MEM_ERROR) throw std::bad_alloc();  // its window, at the first block
    if (status == Z_BUF_ERROR && z.avail_in == 0 && in_left == 0) {
      result.problem = "the data end before the stream does";
      return result;
    }
    if (status != Z_OK && status != Z_BUF_ERROR) {
      result.problem = z.msg ? z.msg : "zlib error " + std::to_string(status);
      return result;
    }
  }
}

}  // namespace mvox
