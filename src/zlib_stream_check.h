#pragma once
// Checks whole zlib streams (RFC 1950) held in memory: inflates each to its end, so that its
// Adler-32 checksum is verified, and keeps nothing of what it inflates.
//
// Why: libtiff's deflate decoder stops as soon as it has the bytes a strip or tile should
// hold, before the checksum at the end of the stream, so a strip whose data were damaged
// (a flipped bit that still decodes) gives wrong samples without a word. mvox checks each
// deflate strip or tile with this before libtiff decodes it.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mvox {

class ZlibStreamCheck {
 public:
  // Allocates nothing: zlib's state and the scratch buffer come with the first check.
  ZlibStreamCheck();
  ~ZlibStreamCheck();
  ZlibStreamCheck(const ZlibStreamCheck&) = delete;
  ZlibStreamCheck& operator=(const ZlibStreamCheck&) = delete;

  // The problem with the zlib stream at bytes[0, size), or "" when it inflates to its end with
  // a matching checksum. The problem is zlib's message ("incorrect data check", "invalid
  // distance too far back", ...) or "the data end before the stream does". Bytes after the
  // end of the stream are ignored, as zlib and libtiff ignore them. Throws std::bad_alloc when
  // zlib cannot get its state.
  std::string problem(const unsigned char* bytes, std::size_t size);

  // The most memory a check holds: the scratch buffer the output goes through, zlib's
  // inflate state and its 32 KiB window.
  static constexpr std::uint64_t kWorkingBytes = 32 * 1024 + 8 * 1024 + 32 * 1024;

 private:
  struct Stream;  // zlib's z_stream, kept out of this header
  std::unique_ptr<Stream> stream_;
  std::vector<unsigned char> scratch_;
};

}  // namespace mvox
