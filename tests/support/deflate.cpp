#include "deflate.h"

#include <gtest/gtest.h>
#include <zlib.h>

namespace mvox::test {

std::vector<unsigned char> deflate_bytes(const std::vector<unsigned char>& data, bool gzip) {
  z_stream stream{};
  // windowBits 15 + 16 asks deflate for a gzip header and trailer instead of zlib's.
  EXPECT_EQ(deflateInit2(&stream, 9, Z_DEFLATED, gzip ? 15 + 16 : 15, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::vector<unsigned char> out(deflateBound(&stream, data.size()) + 64);
  stream.next_in = const_cast<unsigned char*>(data.data());
  stream.avail_in = static_cast<uInt>(data.size());
  stream.next_out = out.data();
  stream.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&stream, Z_FINISH), Z_STREAM_END);
  out.resize(stream.total_out);
  deflateEnd(&stream);
  return out;
}

namespace {

void put_big_endian(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((value >> shift) & 0xff);
}

void put_chunk(std::string& out, const char* type, const std::string& data) {
  put_big_endian(out, static_cast<std::uint32_t>(data.size()));
  const std::string typed = std::string(type, 4) + data;
  out += typed;
  put_big_endian(out, static_cast<std::uint32_t>(
                          crc32(0, reinterpret_cast<const Bytef*>(typed.data()), typed.size())));
}

}  // namespace

std::string png_file(std::uint32_t width, std::uint32_t height, int bit_depth,
                     const std::vector<unsigned char>& idat) {
  std::string file = "\x89PNG\r\n\x1a\n";
  std::string header;
  put_big_endian(header, width);
  put_big_endian(header, height);
  header += static_cast<char>(bit_depth);
  header += std::string(4, '\0');  // grey, deflate, adaptive filters, not interlaced
  put_chunk(file, "IHDR", header);
  put_chunk(file, "IDAT", std::string(idat.begin(), idat.end()));
  put_chunk(file, "IEND", "");
  return file;
}

}  // namespace mvox::test
