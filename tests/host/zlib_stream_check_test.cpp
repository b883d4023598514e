// ZlibStreamCheck (src/read/zlib_stream_check.h) reused from stream to stream, as the TIFF
// reader reuses one for every deflate strip and tile: each stream is inflated with its own
// counts, whatever the last one left (found by tiff_stack_fuzzer: a strip that inflated past
// its bytes handed the next strip 32 KiB of room in a 42-byte place).
#include "read/zlib_stream_check.h"

#include <zlib.h>

#include <cstdint>
#include <vector>

#include "gtest/gtest.h"

namespace mvox {
namespace {

using Bytes = std::vector<unsigned char>;

Bytes pattern(std::size_t size, unsigned seed) {
  Bytes bytes(size);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<unsigned char>(i * 7 + seed);
  return bytes;
}

Bytes zlib_stream(const Bytes& data) {
  uLongf size = compressBound(static_cast<uLong>(data.size()));
  Bytes stream(size);
  EXPECT_EQ(compress2(stream.data(), &size, data.data(), static_cast<uLong>(data.size()), 9), Z_OK);
  stream.resize(size);
  return stream;
}

constexpr unsigned char kGuard = 0xAB;

// Inflates `stream` into a place of `room` bytes followed by guard bytes; checks the guard.
ZlibStreamCheck::Result inflate_guarded(ZlibStreamCheck& check, const Bytes& stream,
                                        std::size_t room, Bytes* placed) {
  Bytes out(room + 4096, kGuard);
  const ZlibStreamCheck::Result result =
      check.inflate(stream.data(), stream.size(), out.data(), room);
  for (std::size_t i = room; i < out.size(); ++i) {
    EXPECT_EQ(out[i], kGuard) << "written past the " << room << " bytes given, at " << i;
    if (out[i] != kGuard) break;
  }
  placed->assign(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(room));
  return result;
}

TEST(ZlibStreamCheck, AStreamLargerThanItsPlaceLeavesNoRoomToTheNext) {
  ZlibStreamCheck check;
  Bytes placed;
  // 600 bytes into 50: the rest through the scratch buffer, to the checksum.
  const Bytes first = pattern(600, 1);
  ZlibStreamCheck::Result result = inflate_guarded(check, zlib_stream(first), 50, &placed);
  EXPECT_EQ(result.problem, "");
  EXPECT_EQ(result.total, 600u);
  EXPECT_EQ(placed, Bytes(first.begin(), first.begin() + 50));
  // Then 300 bytes into 42: 42 placed, nothing beyond them.
  const Bytes second = pattern(300, 2);
  result = inflate_guarded(check, zlib_stream(second), 42, &placed);
  EXPECT_EQ(result.problem, "");
  EXPECT_EQ(result.total, 300u);
  EXPECT_EQ(placed, Bytes(second.begin(), second.begin() + 42));
}

TEST(ZlibStreamCheck, BytesAfterAStreamAreNotReadAsTheNextOnes) {
  ZlibStreamCheck check;
  Bytes placed;
  const Bytes first = pattern(200, 3);
  Bytes stored = zlib_stream(first);
  stored.insert(stored.end(), 40, 0x5A);  // a strip stored longer than its stream
  ZlibStreamCheck::Result result = inflate_guarded(check, stored, 200, &placed);
  EXPECT_EQ(result.problem, "");
  EXPECT_EQ(placed, first);
  const Bytes second = pattern(120, 4);
  result = inflate_guarded(check, zlib_stream(second), 120, &placed);
  EXPECT_EQ(result.problem, "");
  EXPECT_EQ(result.total, 120u);
  EXPECT_EQ(placed, second);
  // A stream cut in half, followed in memory by its other half: the reader is given the first
  // half only, and must stop there, however many bytes the last stream left unread.
  stored = zlib_stream(first);
  stored.insert(stored.end(), 1000, 0x5A);
  inflate_guarded(check, stored, 200, &placed);
  const Bytes whole = zlib_stream(pattern(300, 5));
  Bytes out(300);
  result = check.inflate(whole.data(), whole.size() / 2, out.data(), out.size());
  EXPECT_EQ(result.problem, "the data end before the stream does");
}

}  // namespace
}  // namespace mvox
