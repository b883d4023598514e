#pragma once
// Reads TIFF files as one stack of slices through libtiff: every page (directory) of every
// file, files in the given order and pages in file order, one page decoded at a time. A
// multi-page TIFF is a whole volume in one file; single-page TIFF slices work the same way.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"

namespace mvox {

// Pages must be single-channel (min-is-black) 8-bit unsigned, 16-bit unsigned, 16-bit signed or
// 32-bit float, all of the first page's size and type; striped or tiled, any compression libtiff
// decodes. The constructor walks every page of every file once, reading only the directories,
// and refuses before any slice is read: an unreadable file or directory, a colour, palette,
// min-is-white or multi-sample page, another bit depth or sample format, a page of another size
// or type than the first (named by file and 1-based page number), and a page whose strips or
// tiles lie beyond the end of its file (truncated).
// info(): width, height, type of the first page; depth = all pages. Spacing 1,1,1, unless the
// first file is an ImageJ stack whose ImageDescription gives "spacing=" (the z spacing); then x
// and y come from its XResolution and YResolution (pixels per unit) and z from that.
// Memory: one slice buffer, reused, plus one tile for tiled pages and libtiff's directory.
// Throws mvox::Error naming the file (and page) for every problem, including decoding errors
// met while streaming.
class TiffStackSource : public SliceSource {
 public:
  explicit TiffStackSource(std::vector<std::string> files);
  ~TiffStackSource() override;

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;

  struct Tiff;  // an open libtiff handle and the errors it reported

 private:
  void check_file(std::size_t file_index, std::uint64_t* pages);
  void read_page(std::vector<unsigned char>& buffer);

  std::vector<std::string> files_;
  std::vector<std::uint64_t> pages_per_file_;  // counted by the constructor
  VolumeInfo info_;
  std::vector<unsigned char> buffer_;  // the current slice, native order
  std::vector<unsigned char> tile_;    // one decoded tile of a tiled page
  std::unique_ptr<Tiff> open_;         // the file being streamed
  std::size_t file_index_ = 0;         // of open_
  std::uint64_t page_in_file_ = 0;     // 0-based page of open_ that next_slice reads next
  std::uint32_t next_index_ = 0;       // slice of the stack that next_slice returns next
};

// True when `path` ends in .tif or .tiff, case-insensitive.
bool has_tiff_extension(const std::string& path);

// The number of pages of the TIFF file `path`. Throws mvox::Error naming the file when it
// cannot be opened or a directory cannot be read.
std::uint64_t tiff_page_count(const std::string& path);

}  // namespace mvox
