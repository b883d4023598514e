#include "read/image_stack/image_stack_source.h"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <new>
#include <utility>

#include "error.h"
#include "modules/image_codecs.h"
#include "read/buffer_allocation.h"
#include "read/file_bytes.h"
#include "read/file_names.h"
#include "read/image_stack/image_file_check.h"
#include "read/image_stack/image_header.h"
#include "read/image_stack/jpeg_slice_decoder.h"
#include "read/image_stack/png_slice_decoder.h"

namespace mvox {
namespace {

// Human wording of a sample type for messages, as OpenCV's depths were worded.
std::string depth_text(SampleType type) {
  switch (type) {
    case SampleType::u8: return "8-bit unsigned";
    case SampleType::u16: return "16-bit unsigned";
    case SampleType::i16: return "16-bit signed";
    case SampleType::f32: return "32-bit float";
  }
  return "unknown";
}

std::string size_text(std::uint32_t width, std::uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// True for files mvox decodes itself (PNG with libpng, JPEG with libjpeg), by their names: the
// others need OpenCV's module.
bool decoded_without_opencv(const std::string& path) {
  const std::string extension = lowercase_extension(path);
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg";
}

// Refuses an image whose header shows it is not a slice like `info` (the first slice, named
// `first`), before anything is decoded: not grey, too large, or of another size or depth.
void check_header(const std::string& path, const ImageHeader& header, const VolumeInfo& info,
                  const std::string& first) {
  if (header.channels != 1)
    throw Error(path, "colour image (" + std::to_string(header.channels) +
                          " channels): convert to grayscale first");
  if (first.empty()) {
    const std::string problem = image_size_problem(header);
    if (!problem.empty()) throw Error(path, problem);
    return;
  }
  if (header.width != info.width || header.height != info.height)
    throw Error(path, "image is " + size_text(header.width, header.height) + ", expected " +
                          size_text(info.width, info.height) + " like the first slice (" + first +
                          ")");
  if (header.type != info.type && info.type != SampleType::i16)
    throw Error(path, "image is " + depth_text(header.type) + ", expected " +
                          depth_text(info.type) + " like the first slice (" + first + ")");
  const std::string problem = image_size_problem(header);  // data too short for the image
  if (!problem.empty()) throw Error(path, problem);
}

// Reads `path` into `bytes` and checks what its header says, before any decoder sees it.
void read_checked_file(const std::string& path, ReadBuffer& bytes, const VolumeInfo& info,
                       const std::string& first) {
  try {
    // Reused from slice to slice, so it stops growing.
    read_file_bytes(path, bytes, std::numeric_limits<std::uint64_t>::max(),
                    FileKinds::only_regular);
  } catch (const Error&) {
    // Asked only on failure: a stat before every slice cost one more system call a slice.
    std::error_code error;
    if (!std::filesystem::exists(path, error)) throw Error(path, "no such file");
    throw;
  }
  // A truncated PNG or JPEG would make libpng or libjpeg print on standard error, or decode
  // into a wrong slice (image_file_check.h).
  const std::string problem = image_file_problem(bytes.data(), bytes.size());
  if (!problem.empty()) throw Error(path, problem);
  if (const std::optional<ImageHeader> header = parse_image_header(bytes.data(), bytes.size()))
    check_header(path, *header, info, first);
}

}  // namespace

ImageStackSource::ImageStackSource(std::vector<std::string> paths)
    : files_(std::make_shared<const std::vector<std::string>>(std::move(paths))) {
  if (files().empty()) throw Error("INPUT", "no slice image files");
  if (files().size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("INPUT", "more than 2^32-1 slice files");
  }
  info_.depth = static_cast<std::uint32_t>(files().size());
  const std::string& first = files()[0];
  std::error_code error;
  if (!std::filesystem::exists(first, error)) throw Error(first, "no such file");
  first_file_bytes_ = std::filesystem::file_size(first, error);
  if (error) first_file_bytes_ = 0;
  // OpenCV is loaded now, before the run, when a slice will need it: a missing module is found
  // before the first slice, and its memory counts as the program's in the run's plan.
  uses_opencv_ = !std::all_of(files().begin(), files().end(), decoded_without_opencv);
  const std::optional<ImageHeader> header = read_image_header(first);
  if (header && header->format == ImageFormat::png && !uses_opencv_) {
    // A PNG that is not plain grey (grey with alpha or a transparent value) is OpenCV's to read.
    ReadBuffer start;
    read_file_bytes(first, start, 1 << 20, FileKinds::only_regular);
    if (!is_plain_grey_png(start.data(), start.size())) uses_opencv_ = true;
  }
  if (uses_opencv_) load_image_codecs(first);
  if (!header) {
    load(0);  // a format whose header mvox does not read: the decoder tells
    return;
  }
  check_header(first, *header, info_, "");
  info_.width = header->width;
  info_.height = header->height;
  info_.type = header->type;
  row_bytes_ = static_cast<std::size_t>(info_.width) * sample_bytes(info_.type);
}

std::uint64_t ImageStackSource::working_bytes() const {
  const std::uint64_t slice = std::uint64_t{row_bytes_} * info_.height;
  // The slice buffer, OpenCV's decoded image when OpenCV decodes (one more slice; libpng and
  // libjpeg decode into the slice buffer), and one file's bytes. The files of a stack are of
  // much the same size, so twice the first one's (and 1 MiB) allows for the largest; a
  // compressed slice is not larger than its samples in any case.
  const std::uint64_t file = std::min(slice + 64 * 1024, 2 * first_file_bytes_ + (1 << 20));
  return (uses_opencv_ ? 2 : 1) * slice + std::max(file, first_file_bytes_);
}

unsigned char* ImageStackSource::slice_buffer(const std::string& path, std::uint32_t width,
                                              std::uint32_t height, SampleType type, int channels,
                                              const std::string& depth) {
  if (channels != 1) {
    throw Error(path, "colour image (" + std::to_string(channels) +
                          " channels): convert to grayscale first");
  }
  if (info_.width == 0) {  // the first slice, whose header could not be read
    info_.width = width;
    info_.height = height;
    info_.type = type;
    row_bytes_ = static_cast<std::size_t>(width) * sample_bytes(type);
  } else {
    if (width != info_.width || height != info_.height) {
      throw Error(path, "image is " + size_text(width, height) + ", expected " +
                            size_text(info_.width, info_.height) + " like the first slice (" +
                            files()[0] + ")");
    }
    if (type != info_.type) {
      throw Error(path, "image is " + depth + ", expected " + depth_text(info_.type) +
                            " like the first slice (" + files()[0] + ")");
    }
  }
  if (buffer_.empty())
    resize_buffer(buffer_, std::uint64_t{row_bytes_} * info_.height, path, "a slice");
  return buffer_.data();
}

void ImageStackSource::load(std::size_t index) {
  const std::string& path = files()[index];
  // Until the first slice's size is known there is nothing to compare a header with.
  read_checked_file(path, file_bytes_, info_, info_.width == 0 ? std::string() : files()[0]);
  const unsigned char* bytes = file_bytes_.data();
  const std::size_t size = file_bytes_.size();
  // Every decoder writes straight into the slice buffer, after its image is checked against
  // the first slice.
  if (is_jpeg_file(bytes, size)) {
    // Strictly, without OpenCV, whose libjpeg returns damaged scans as good slices with only a
    // warning on standard error (jpeg_slice_decoder.h).
    decode_jpeg_slice(path, bytes, size, [&](std::uint32_t width, std::uint32_t height) {
      return slice_buffer(path, width, height, SampleType::u8, 1, depth_text(SampleType::u8));
    });
  } else if (is_plain_grey_png(bytes, size)) {
    // read_checked_file has checked every chunk's CRC.
    decode_png_slice(
        path, bytes, size,
        [&](std::uint32_t width, std::uint32_t height, SampleType type) {
          return slice_buffer(path, width, height, type, 1, depth_text(type));
        },
        PngCrcs::checked_already);
  } else {
    decode_image_with_opencv(path, bytes, size, [&](const DecodedImageShape& shape) {
      if (shape.channels == 1 && !shape.readable && info_.width == 0)
        throw Error(path,
                    "image is " + shape.depth_text + ", expected 8-bit or 16-bit integer samples");
      return slice_buffer(path, shape.width, shape.height,
                          shape.readable ? shape.type : SampleType::f32, shape.channels,
                          shape.depth_text);
    });
  }
  loaded_index_ = index;
}

std::unique_ptr<SliceSource> ImageStackSource::open_range(std::uint32_t first,
                                                          std::uint32_t end) const {
  // A copy knows the volume as this source does (its size, type, first file for messages, and
  // whether OpenCV is needed, whose module is loaded already); it keeps the decoded first slice
  // only when it starts there.
  auto range = std::make_unique<ImageStackSource>(*this);
  range->next_index_ = first;
  range->end_index_ = end;
  range->file_bytes_ = {};
  if (loaded_index_ != first) {
    range->buffer_ = {};
    range->loaded_index_ = SIZE_MAX;
  }
  return range;
}

bool ImageStackSource::next_slice(SliceView* slice) {
  if (next_index_ >= std::min(files().size(), end_index_)) return false;
  // The constructor already decoded the first file; do not decode it twice.
  if (next_index_ != loaded_index_) load(next_index_);
  slice->samples = buffer_.data();
  slice->width = info_.width;
  slice->height = info_.height;
  slice->row_stride_bytes = row_bytes_;
  slice->type = info_.type;
  ++next_index_;
  return true;
}

}  // namespace mvox
