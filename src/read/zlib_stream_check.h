#pragma once
// Inflates whole zlib streams (RFC 1950) held in memory, to their end, so that their Adler-32
// checksum is verified: the first bytes go where the caller wants them, the rest through a
// small scratch buffer.
//
// Why: libtiff's deflate decoder stops as soon as it has the bytes a strip or tile should
// hold, so it checks the checksum only when the stream happens to end there: a strip whose
// stream holds more (a writer storing whole strips at the bottom of a page) and whose data
// were damaged gives wrong samples without a word. mvox inflates deflate strips and tiles with
// this instead.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mvox {

class ZlibStreamCheck {
 public:
  // Allocates nothing: zlib's state and the scratch buffer come with the first stream.
  ZlibStreamCheck();
  ~ZlibStreamCheck();
  ZlibStreamCheck(const ZlibStreamCheck&) = delete;
  ZlibStreamCheck& operator=(const ZlibStreamCheck&) = delete;

  struct Result {
    // "" when the stream inflated to its end with a matching checksum; otherwise zlib's message
    // ("incorrect data check", "invalid distance too far back", ...) or "the data end before
    // the stream does".
    std::string problem;
    std::uint64_t total = 0;  // bytes inflated, all of them
  };
  // Inflates the zlib stream at bytes[0, size) to its end; the first `out_bytes` bytes it
  // holds go to out[0, out_bytes) (fewer when it holds fewer: see `total`). Bytes after the
  // end of the stream are ignored, as zlib and libtiff ignore them. Throws std::bad_alloc when
  // zlib cannot get its state.
  Result inflate(const unsigned char* bytes, std::size_t size, unsigned char* out,
                 std::size_t out_bytes);

  // The most memory it holds: the scratch buffer, zlib's inflate state and its 32 KiB window.
  static constexpr std::uint64_t kWorkingBytes = 32 * 1024 + 8 * 1024 + 32 * 1024;

 private:
  struct Stream;  // zlib's z_stream, kept out of this header
  std::unique_ptr<Stream> stream_;
  std::vector<unsigned char> scratch_;
};

}  // namespace mvox
