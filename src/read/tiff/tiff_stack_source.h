#pragma once
// Reads TIFF files as one stack of slices: every page (directory) of every file, files in the
// given order and pages in file order, one page decoded at a time. A multi-page TIFF is a whole
// volume in one file; single-page TIFF slices work the same way. mvox reads the directories
// (tiff_directory.h), uncompressed data and deflate data itself; only pages of other codecs (and
// deflate with the floating-point predictor) load libtiff, in the TIFF module (tiff_file.h), to
// decode them; libtiff reads their directories too, when the stack is opened, and must read
// them as mvox does.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/copied_slices.h"
#include "read/range_readable.h"
#include "read/read_buffer.h"
#include "read/tiff/tiff_directory.h"
#include "read/zlib_stream_check.h"

namespace mvox {

class TiffFile;

// Pages must be single-channel (min-is-black) 8-bit unsigned, 16-bit unsigned, 16-bit signed or
// 32-bit float, all of the first page's size and type; striped or tiled, any compression libtiff
// decodes. The constructor walks every page of every file once, reading only the directories,
// and refuses before any slice is read: an unreadable file or directory, a colour, palette,
// min-is-white or multi-sample page, another bit depth or sample format, a page of another size
// or type than the first (named by file and 1-based page number), a page whose strips or
// tiles lie beyond the end of its file (truncated), a compression that no code here decodes,
// a page whose directory libtiff, decoding it, refuses or reads otherwise than mvox, and a
// header that lies about sizes:
// - a strip or tile, or a whole page, that declares more decoded bytes than its stored bytes
//   can decode to (compression_bounds.h: uncompressed exactly, deflate, LZW, PackBits and
//   JPEG by their ratios; codecs without a bound, such as LZMA or Zstandard, are left to the
//   memory budget), named by page, strip or tile, and both sizes;
// - tiles far larger than the image they tile: a tile may hold the image rounded up to
//   multiples of 16 (TIFF's tile granularity) or 4096x4096 samples, whichever is more.
// While streaming, a deflate strip or tile whose zlib checksum is wrong (which libtiff does not
// check) is refused naming page and strip or tile.
// info(): width, height, type of the first page; depth = all pages. Spacing 1,1,1, unless the
// first file is an ImageJ stack whose ImageDescription gives "spacing=" (the z spacing); then x
// and y come from its XResolution and YResolution (pixels per unit) and z from that.
// Memory: one directory at a time, and where every 16th page's directory is (8 bytes per 16
// pages), until the first slice is read; then one slice
// buffer, reused, plus one tile for tiled pages, the largest stored strip or tile of compressed
// pages, the deflate check's scratch and the current page's strip or tile locations:
// working_bytes(), an upper bound known from the directories.
// Throws mvox::Error naming the file (and page) for every problem, including decoding errors
// met while streaming and allocations that fail (naming the bytes asked for).
// A file is read anywhere (RangeReadable): each slab worker opens its own files and walks
// the directories up to its first page, so that decoding runs in parallel too.
class TiffStackSource : public SliceSource, public RangeReadable, public CopiedSlices {
 public:
  explicit TiffStackSource(std::vector<std::string> files);
  ~TiffStackSource() override;

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;
  // The slice, the largest tile, the largest stored strip or tile that libtiff or the deflate
  // check reads whole (rounded up as libtiff allocates), the deflate check's own buffers, and
  // the largest page's strip or tile locations. libtiff's own state (its codec's, tens of KiB,
  // and its copy of a directory) is not counted.
  std::uint64_t working_bytes() const override;

  bool range_readable() const override { return true; }
  std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const override;
  // No page is compressed (the directories, all read when the stack was opened, say so).
  bool slices_are_copied() const override { return !compressed_pages_; }

 private:
  // A source of slices [first, end) of `whole`'s stack, which has walked every directory.
  TiffStackSource(const TiffStackSource& whole, std::uint32_t first, std::uint32_t end);
  void check_file(std::size_t file_index, std::uint64_t* pages);
  void read_page(ReadBuffer& buffer);
  // Decodes strip or tile `index` of the current page, rows of `row_samples` samples, into
  // out[0, out_bytes), or throws naming page and strip or tile. Deflate data are inflated whole
  // here, so that their checksum is checked (zlib_stream_check.h).
  void read_chunk(std::uint32_t index, unsigned char* out, std::size_t out_bytes,
                  std::size_t row_samples);
  // Opens the current file in libtiff if it is not yet, moves it to the current page, and
  // checks that libtiff reads the page's directory as mvox did.
  void position_libtiff();

  // What the constructor learnt of the files, shared by the ranges rather than copied for every
  // slab (a folder of single-page TIFF slices is a file per slice).
  struct Files {
    std::vector<std::string> paths;
    std::vector<std::uint64_t> pages;  // of each file
    // Where the directory of every kPagesPerMark-th page of each file is (file by file, from
    // page 0): a range starts there and reads at most kPagesPerMark - 1 directories before
    // its first page, instead of every directory before it. 8 bytes per 16 pages.
    std::vector<std::vector<std::uint64_t>> directory_marks;
  };
  static constexpr std::uint64_t kPagesPerMark = 16;
  std::shared_ptr<Files> files_ = std::make_shared<Files>();
  VolumeInfo info_;
  ReadBuffer buffer_;  // the current slice, native order; from the first slice
  ReadBuffer tile_;    // one decoded tile of a tiled page
  ReadBuffer raw_;     // one stored deflate strip or tile
  std::unique_ptr<ZlibStreamCheck> deflate_check_;  // from the first deflate page
  // Upper bounds over every page, from the directories (working_bytes()).
  std::uint64_t largest_tile_ = 0;             // decoded bytes of the largest tile
  std::uint64_t largest_deflate_chunk_ = 0;    // stored bytes of the largest deflate strip or tile
  std::uint64_t largest_libtiff_chunk_ = 0;    // ... of other compressed pages, which libtiff reads
  std::uint64_t largest_chunk_count_ = 0;      // strips or tiles of the page with the most
  bool compressed_pages_ = false;              // any page's data compressed
  std::unique_ptr<TiffDirectoryReader> open_;  // the file being streamed
  TiffDirectory page_;                         // the page of open_ being read
  std::unique_ptr<TiffFile> libtiff_;  // open_ in libtiff, once a page needs libtiff to decode
  std::uint64_t libtiff_page_ = 0;     // 0-based page libtiff_ is at
  std::size_t file_index_ = 0;         // of open_
  std::uint64_t page_in_file_ = 0;     // 0-based page of open_ that next_slice reads (next)
  std::uint32_t next_index_ = 0;       // slice of the stack that next_slice returns next
  std::uint32_t end_index_ = 0;        // one past the last slice it returns (depth, or a range's)
};

// True when `path` ends in .tif or .tiff, case-insensitive.
bool has_tiff_extension(const std::string& path);

// The number of pages of the TIFF file `path`. Throws mvox::Error naming the file when it
// cannot be opened or a directory cannot be read.
std::uint64_t tiff_page_count(const std::string& path);

}  // namespace mvox
