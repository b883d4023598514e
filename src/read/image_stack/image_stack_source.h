#pragma once
// Reads a volume stored as one grayscale image per slice (PNG, TIFF, JPEG, BMP, PGM): grey PNG
// through libpng (png_slice_decoder.h) and JPEG through libjpeg, strictly
// (jpeg_slice_decoder.h); every other format through OpenCV, whose module
// (modules/image_codecs.h) is loaded only when a slice's file name or the first PNG needs it.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/range_readable.h"
#include "read/read_buffer.h"

namespace mvox {

// Slices come from `files` in the given order (list_input_files sorts them). The first file fixes
// width, height and sample type, read from its header (image_header.h) by the constructor, so
// info() is exact before any slice is decoded: depth = files.size(), spacing 1,1,1 (image files
// carry none we trust). Only a first file whose format has no header mvox reads (a TIFF among
// other images) is decoded by the constructor.
// Accepted images: one channel, 8-bit unsigned (u8), 16-bit unsigned (u16) or 16-bit signed (i16).
// Every slice's header is checked against the first before it is decoded, so a slice that
// declares another or a gigantic size is refused before a decoder allocates for it.
// Memory: one slice buffer, reused for every slice and allocated at the first, plus the slice's
// file while it is decoded, and OpenCV's decoded image when OpenCV decodes (working_bytes()).
// Throws mvox::Error naming the file for an unreadable or corrupt image, a colour image, an
// unsupported bit depth, a size or bit depth that differs from the first slice, an image of
// more than 2^30 pixels (OpenCV's limit), or, when a slice needs OpenCV, a module that cannot
// be loaded.
class ImageStackSource : public SliceSource, public RangeReadable {
 public:
  explicit ImageStackSource(std::vector<std::string> files);

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override;

  bool range_readable() const override { return true; }
  std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const override;

 private:
  // Decodes files_[index] into buffer_, checking it against info_ (or setting info_ for the
  // first file).
  void load(std::size_t index);
  // The slice buffer for a decoded image of `path`, once the image is checked against info_
  // (or has set it, for the first file); `depth` words the image's sample type for messages.
  unsigned char* slice_buffer(const std::string& path, std::uint32_t width, std::uint32_t height,
                              SampleType type, int channels, const std::string& depth);

  const std::vector<std::string>& files() const { return *files_; }

  // Shared by the ranges: a slab's range copying the list of every slice, for every slab,
  // cost time in the number of slabs times the number of slices.
  std::shared_ptr<const std::vector<std::string>> files_;
  VolumeInfo info_;
  std::vector<unsigned char> buffer_;  // the current slice, rows packed, native order
  ReadBuffer file_bytes_;              // the current slice's file, while it is decoded
  std::size_t row_bytes_ = 0;
  std::uint64_t first_file_bytes_ = 0;  // size of the first file, for working_bytes()
  bool uses_opencv_ = false;            // some slice is decoded by OpenCV
  std::size_t next_index_ = 0;          // file the next call to next_slice returns
  std::size_t end_index_ = SIZE_MAX;    // one past the last file it returns (open_range)
  // File whose samples are in buffer_: the constructor decodes the first one only when its
  // header cannot be read.
  std::size_t loaded_index_ = SIZE_MAX;
};

}  // namespace mvox
