#pragma once
// Reads a volume stored as one grayscale image per slice (PNG, TIFF, JPEG, BMP, PGM) via OpenCV;
// JPEG via libjpeg directly, strictly (jpeg_slice_decoder.h).
#include <cstddef>
#include <string>
#include <vector>

#include "mvox/slice_source.h"

namespace mvox {

// Slices come from `files` in the given order (list_input_files sorts them). The first file fixes
// width, height and sample type and is decoded in the constructor, so info() is exact before any
// slice is requested: depth = files.size(), spacing 1,1,1 (image files carry none we trust).
// Accepted images: one channel, 8-bit unsigned (u8), 16-bit unsigned (u16) or 16-bit signed (i16).
// Memory: one slice buffer, reused for every slice, plus the slice's file and OpenCV's decoded
// image while a slice is being decoded and copied.
// Throws mvox::Error naming the file for an unreadable or corrupt image, a colour image, an
// unsupported bit depth, or a size or bit depth that differs from the first slice.
class ImageStackSource : public SliceSource {
 public:
  explicit ImageStackSource(std::vector<std::string> files);

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;

 private:
  // Decodes files_[index] into buffer_, checking it against info_ (or setting info_ for the
  // first file).
  void load(std::size_t index);

  std::vector<std::string> files_;
  VolumeInfo info_;
  std::vector<unsigned char> buffer_;      // the current slice, rows packed, native order
  std::vector<unsigned char> file_bytes_;  // the current slice's file, while it is decoded
  std::size_t row_bytes_ = 0;
  std::size_t next_index_ = 0;    // file the next call to next_slice returns
  std::size_t loaded_index_ = 0;  // file whose samples are in buffer_
};

}  // namespace mvox
