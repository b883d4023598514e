#pragma once
// Test support: compressed test data made with zlib, as NRRD (gzip), MetaImage (zlib) and PNG
// (zlib in IDAT chunks) store it.
#include <cstdint>
#include <string>
#include <vector>

namespace mvox::test {

// `data` compressed with zlib, as a gzip member (gzip) or a zlib stream.
std::vector<unsigned char> deflate_bytes(const std::vector<unsigned char>& data, bool gzip);

// A grey PNG file: its IHDR declares `width` x `height` at `bit_depth`, and its IDAT chunk holds
// `idat` (the compressed rows; anything, for files that lie), every CRC correct.
std::string png_file(std::uint32_t width, std::uint32_t height, int bit_depth,
                     const std::vector<unsigned char>& idat);

}  // namespace mvox::test
