#pragma once
// TIFF's directories (one per page) read by mvox itself: classic TIFF and BigTIFF, either byte
// order. libtiff (in the TIFF module, tiff_file.h) is left only the decoding of compressed data
// that mvox does not inflate itself: loading libtiff and its seven codec libraries, and its
// reading of every directory (about 25 us a page), made a TIFF run start half again slower than
// a raw one. With this, a stack of uncompressed or deflate pages never loads libtiff.
//
// Only the tags the TIFF stack reader looks at are read; the others are skipped by their tag
// number alone. What a directory says is checked only as far as reading it needs (entries and
// arrays inside the file, directories that do not loop, offsets and byte counts for every
// strip or tile); what a page may hold is the stack reader's to decide (tiff_stack_source.h).
// ImageDescription and the resolutions, which mvox could do without, read as absent when
// damaged, as libtiff reads them.
// Memory: one directory and its strip or tile locations, whatever the number of pages.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mvox {

class RawFile;

// One page's tags, with TIFF's defaults where a tag is absent.
struct TiffDirectory {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint16_t samples_per_pixel = 1;
  std::uint16_t bits_per_sample = 1;
  std::uint16_t sample_format = 1;  // unsigned
  std::uint16_t photometric = 1;    // min-is-black when absent, as most readers take it
  std::uint16_t compression = 1;    // none
  std::uint16_t fill_order = 1;     // most significant bit first
  std::uint16_t predictor = 1;      // none
  bool tiled = false;
  std::uint32_t tile_width = 0;  // tiled pages
  std::uint32_t tile_height = 0;
  std::uint32_t rows_per_strip = 0;  // striped pages: as stored, or the page's height when absent
  // Where each strip or tile is stored, exactly as many as the page has.
  // An uncompressed page without byte counts gets the bytes its strips or tiles decode to,
  // as libtiff gives it.
  std::vector<std::uint64_t> chunk_offsets;
  std::vector<std::uint64_t> chunk_bytes;
  std::string description;  // ImageDescription's first 64 KiB, to its first NUL; "" if absent
  float x_resolution = 0;   // pixels per unit; 0 when absent
  float y_resolution = 0;

  // Rows per strip within the page: at least 1 and at most the height (0 for an empty page).
  std::uint32_t strip_rows() const;
  // The strip holding row y, or the tile holding sample (x, y).
  std::uint32_t chunk_at(std::uint32_t x, std::uint32_t y) const;
};

// Reads one TIFF file's directories in order, and the bytes of its strips and tiles. Every
// problem throws mvox::Error naming the file and, for a directory, its page (1-based).
class TiffDirectoryReader {
 public:
  // Opens `path` and reads its header. Throws when the file cannot be opened, is a pipe (TIFF's
  // directories may be anywhere in a file), or does not start with a TIFF header.
  explicit TiffDirectoryReader(const std::string& path);
  ~TiffDirectoryReader();
  TiffDirectoryReader(const TiffDirectoryReader&) = delete;
  TiffDirectoryReader& operator=(const TiffDirectoryReader&) = delete;

  const std::string& path() const { return path_; }
  std::uint64_t file_bytes() const { return file_bytes_; }
  // The file's byte order is not the machine's: its 16- and 32-bit samples need swapping.
  bool byte_swapped() const { return byte_swapped_; }

  // Reads the next page's directory into `page`: false after the last one.
  bool next(TiffDirectory* page);
  // Where the directory next() reads is (0 after the last one), and going on from one such
  // place, as found by an earlier reader of the same file: to start at a page without reading
  // the directories before it. `pages_before` is that page's 0-based number, for messages.
  std::uint64_t next_directory() const { return next_directory_; }
  // Where the directory next() read last is.
  std::uint64_t directory() const { return directory_offset_; }
  void go_to_directory(std::uint64_t offset, std::uint64_t pages_before);

  // Reads exactly `bytes` bytes at `offset` (a strip or tile, inside the file as checked).
  void read_at(std::uint64_t offset, unsigned char* out, std::size_t bytes);

 private:
  struct Entry;
  void read_directory(std::uint64_t offset, TiffDirectory* page);
  std::uint64_t integer(const Entry& entry, std::uint64_t index, const std::string& where);
  void read_integers(const Entry& entry, std::uint64_t count, std::vector<std::uint64_t>* values,
                     const std::string& where);
  float rational(const Entry& entry, const std::string& where);
  std::string text(const Entry& entry, const std::string& where);
  // Whether `entry`'s values (the first 64 KiB of them) lie in the file.
  bool values_in_file(const Entry& entry) const;
  // The bytes of `entry`'s values, at most `max_bytes` of them, checked to lie in the file.
  void entry_bytes(const Entry& entry, std::uint64_t max_bytes, std::vector<unsigned char>* out,
                   const std::string& where);
  std::uint64_t unsigned_at(const unsigned char* at, unsigned bytes) const;

  std::string path_;
  std::unique_ptr<RawFile> file_;
  std::uint64_t file_bytes_ = 0;
  bool byte_swapped_ = false;
  bool big_endian_ = false;
  bool big_tiff_ = false;
  std::uint64_t next_directory_ = 0;    // 0 after the last page
  std::uint64_t directory_offset_ = 0;  // of the page next() read last
  std::uint64_t pages_read_ = 0;
  // Directories that loop are found in fixed memory, whatever the number of pages, by Brent's
  // cycle detection: one directory offset is kept, and replaced by the current one after 1, 2,
  // 4, 8, ... more directories; meeting it again is a loop. A loop is found before about three
  // times as many directories as the file has are read (a loop of three pages back to the
  // first: at the sixth).
  std::uint64_t kept_directory_ = 0;
  std::uint64_t directories_until_kept_ = 1;
  std::uint64_t keep_every_ = 1;
  std::vector<unsigned char> directory_;  // the entries of the directory being read
  std::vector<unsigned char> scratch_;    // an array's bytes
  std::vector<std::uint64_t> one_value_;  // a tag's first value
};

}  // namespace mvox
