#pragma once
// Test support: TIFF files written byte by byte (little-endian classic TIFF), for headers that
// libtiff's writer would not produce: tiles far larger than the image, a page far larger than
// its data, strips whose stored bytes are damaged.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mvox::test {

// One page of one-channel min-is-black samples.
struct TiffPageBytes {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint16_t bits = 8;
  std::uint16_t compression = 1;     // TIFF's Compression tag: 1 none, 8 deflate, ...
  std::uint32_t rows_per_strip = 0;  // striped pages; 0: the whole page in one strip
  std::uint32_t tile_width = 0;      // tiled pages, when both are set
  std::uint32_t tile_height = 0;
  std::vector<std::vector<unsigned char>> chunks;  // the strips or tiles, as stored
};

// The bytes of a TIFF file holding `pages`, each chunk stored as given.
std::vector<unsigned char> tiff_file_bytes(const std::vector<TiffPageBytes>& pages);

// Editing such files in place, to break them in one way: little-endian 16- and 32-bit values at
// byte `at`, the offset of page `page`'s directory (0-based), the place of its link to the next
// directory, the place of its entry for `tag` (a failed test when absent), and that entry given
// the tag number `new_tag` (which, for a number mvox does not know, removes the tag).
void put_tiff_u16(std::vector<unsigned char>& bytes, std::size_t at, std::uint32_t value);
void put_tiff_u32(std::vector<unsigned char>& bytes, std::size_t at, std::uint32_t value);
std::uint32_t tiff_directory_offset(const std::vector<unsigned char>& bytes, int page);
std::size_t tiff_next_link(const std::vector<unsigned char>& bytes, int page);
std::size_t tiff_entry_offset(const std::vector<unsigned char>& bytes, int page, std::uint16_t tag);
void rename_tiff_tag(std::vector<unsigned char>& bytes, int page, std::uint16_t tag,
                     std::uint16_t new_tag);

// The 8-bit slices of `samples` (width x height each), from slice `first` on, `count` of them,
// as TIFF pages: uncompressed in one strip, or deflate in strips of `rows_per_strip` rows.
std::vector<TiffPageBytes> tiff_pages_of(const std::string& samples, std::uint32_t width,
                                         std::uint32_t height, std::uint32_t first,
                                         std::uint32_t count, bool deflate,
                                         std::uint32_t rows_per_strip = 0);

// `bytes` as one zlib stream (TIFF's deflate compression).
std::vector<unsigned char> zlib_compressed(const std::vector<unsigned char>& bytes);

}  // namespace mvox::test
