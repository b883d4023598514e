#include "zlib_stream_check.h"

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

std::string ZlibStreamCheck::problem(const unsigned char* bytes, std::size_t size) {
  if (!stream_) {
    auto stream = std::make_unique<Stream>();
    // Only Z_MEM_ERROR is possible here (the version and parameters are right).
    if (inflateInit(&stream->z) != Z_OK) throw std::bad_alloc();
    stream_ = std::move(stream);
    scratch_.resize(32 * 1024);
  } else if (inflateReset(&stream_->z) != Z_OK) {
    return "zlib cannot restart";
  }
  z_stream& z = stream_->z;
  z.next_in = const_cast<unsigned char*>(bytes);  // zlib's API is not const, but only reads
  std::size_t left = size;
  for (;;) {
    // zlib counts in uInt: very large strips go in pieces.
    if (z.avail_in == 0 && left > 0) {
      z.avail_in = static_cast<uInt>(std::min<std::size_t>(left, 1u << 30));
      left -= z.avail_in;
    }
    z.next_out = scratch_.data();
    z.avail_out = static_cast<uInt>(scratch_.size());
    const int status = inflate(&z, Z_NO_FLUSH);
    if (status == Z_STREAM_END) return "";
    if (status == Z_MEM_ERROR) throw std::bad_alloc();  // its window, at the first block
    if (status == Z_BUF_ERROR && z.avail_in == 0 && left == 0)
      return "the data end before the stream does";
    if (status != Z_OK && status != Z_BUF_ERROR)
      return z.msg ? z.msg : "zlib error " + std::to_string(status);
  }
}

}  // namespace mvox
