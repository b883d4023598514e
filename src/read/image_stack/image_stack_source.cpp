#include "read/image_stack/image_stack_source.h"

#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <new>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <utility>

#include "error.h"
#include "read/buffer_allocation.h"
#include "read/file_bytes.h"
#include "read/image_stack/image_file_check.h"
#include "read/image_stack/image_header.h"
#include "read/image_stack/jpeg_slice_decoder.h"
#include "write/slice_image_writer.h"

namespace mvox {
namespace {

// Human wording of an OpenCV depth for messages.
std::string depth_text(int cv_depth) {
  switch (cv_depth) {
    case CV_8U: return "8-bit unsigned";
    case CV_8S: return "8-bit signed";
    case CV_16U: return "16-bit unsigned";
    case CV_16S: return "16-bit signed";
    case CV_32S: return "32-bit integer";
    case CV_32F: return "32-bit float";
    case CV_64F: return "64-bit float";
    default: return "OpenCV depth " + std::to_string(cv_depth);
  }
}

std::string size_text(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

bool to_sample_type(int cv_depth, SampleType* type) {
  switch (cv_depth) {
    case CV_8U: *type = SampleType::u8; return true;
    case CV_16U: *type = SampleType::u16; return true;
    case CV_16S: *type = SampleType::i16; return true;
    default: return false;
  }
}

int to_cv_depth(SampleType type) {
  switch (type) {
    case SampleType::u8: return CV_8U;
    case SampleType::u16: return CV_16U;
    case SampleType::i16: return CV_16S;
    case SampleType::f32: return CV_32F;
  }
  return -1;
}

// The reason in an OpenCV error text "... error: (-2:Unspecified error) REASON in function
// 'f'", or "" when the text has no such part.
std::string opencv_reason(const std::string& text) {
  const std::size_t code = text.find("error: (");
  if (code == std::string::npos) return "";
  const std::size_t start = text.find(") ", code);
  if (start == std::string::npos) return "";
  std::size_t end = text.find(" in function", start);
  if (end == std::string::npos) end = text.find('\n', start);
  std::string reason = text.substr(start + 2, end == std::string::npos ? end : end - start - 2);
  // One line, whatever the decoder wrote.
  for (char& c : reason)
    if (c == '\n' || c == '\r') c = ' ';
  return reason;
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
    throw Error(
        path,
        "image is " + size_text(static_cast<int>(header.width), static_cast<int>(header.height)) +
            ", expected " + size_text(static_cast<int>(info.width), static_cast<int>(info.height)) +
            " like the first slice (" + first + ")");
  if (header.type != info.type && info.type != SampleType::i16)
    throw Error(path, "image is " + depth_text(to_cv_depth(header.type)) + ", expected " +
                          depth_text(to_cv_depth(info.type)) + " like the first slice (" + first +
                          ")");
  const std::string problem = image_size_problem(header);  // data too short for the image
  if (!problem.empty()) throw Error(path, problem);
}

cv::Mat read_image(const std::string& path, std::vector<unsigned char>& bytes,
                   const VolumeInfo& info, const std::string& first) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw Error(path, "no such file");
  read_file_bytes(path, bytes);  // reused from slice to slice, so it stops growing
  // A truncated PNG or JPEG would make libpng or libjpeg print on standard error, or decode
  // into a wrong slice (image_file_check.h).
  const std::string problem = image_file_problem(bytes.data(), bytes.size());
  if (!problem.empty()) throw Error(path, problem);
  if (const std::optional<ImageHeader> header = parse_image_header(bytes.data(), bytes.size()))
    check_header(path, *header, info, first);
  cv::Mat image;
  // JPEG is decoded strictly, without OpenCV, whose libjpeg returns damaged scans as good
  // slices with only a warning on standard error (jpeg_slice_decoder.h).
  if (is_jpeg_file(bytes.data(), bytes.size())) {
    decode_jpeg_slice(
        path, bytes.data(), bytes.size(), [&](std::uint32_t width, std::uint32_t height) {
          try {
            image.create(static_cast<int>(height), static_cast<int>(width), CV_8UC1);
          } catch (const cv::Exception&) {
            throw std::bad_alloc();  // OpenCV's only failure here; the decoder names the bytes
          }
          return image.data;
        });
    return image;
  }
  // OpenCV reports a decoder's failure on std::cerr ("imdecode_(''): can't read data: ..."),
  // a line of its own; mvox gives the reason in its one error line instead. Only this thread
  // decodes (the prefetching reader), and mvox itself never writes to std::cerr (its messages
  // use stdio).
  std::stringbuf decoder_messages;
  {
    // Puts std::cerr back on every way out, exceptions other than OpenCV's included.
    struct CerrRedirect {
      std::streambuf* saved;
      ~CerrRedirect() { std::cerr.rdbuf(saved); }
    } redirect{std::cerr.rdbuf(&decoder_messages)};
    try {
      // ANYDEPTH keeps 16-bit samples (the default would scale them to 8 bits); ANYCOLOR keeps
      // the channel count so colour images are detected instead of silently converted. The
      // Mat wraps the bytes without copying them.
      if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw Error(path, "image file is over 2 GiB, more than OpenCV decodes");
      const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8UC1, bytes.data());
      if (!bytes.empty()) image = cv::imdecode(encoded, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    } catch (const cv::Exception& e) {
      throw Error(path, "cannot decode image: " + e.msg);
    }
  }
  if (image.empty()) {
    const std::string reason = opencv_reason(decoder_messages.str());
    throw Error(path, reason.empty() ? "cannot read image (unreadable, corrupt, truncated or not "
                                       "an image format)"
                                     : "cannot decode image: " + reason);
  }
  return image;
}

}  // namespace

ImageStackSource::ImageStackSource(std::vector<std::string> files) : files_(std::move(files)) {
  if (files_.empty()) throw Error("INPUT", "no slice image files");
  if (files_.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("INPUT", "more than 2^32-1 slice files");
  }
  info_.depth = static_cast<std::uint32_t>(files_.size());
  initialize_image_codecs();  // OpenCV decodes every slice: its registry's memory is the program's
  const std::string& first = files_[0];
  std::error_code error;
  if (!std::filesystem::exists(first, error)) throw Error(first, "no such file");
  first_file_bytes_ = std::filesystem::file_size(first, error);
  if (error) first_file_bytes_ = 0;
  const std::optional<ImageHeader> header = read_image_header(first);
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
  // The slice buffer, OpenCV's decoded image (one more slice), and one file's bytes. The files of
  // a stack are of much the same size, so twice the first one's (and 1 MiB) allows for the
  // largest; a compressed slice is not larger than its samples in any case.
  const std::uint64_t file = std::min(slice + 64 * 1024, 2 * first_file_bytes_ + (1 << 20));
  return 2 * slice + std::max(file, first_file_bytes_);
}

void ImageStackSource::load(std::size_t index) {
  const std::string& path = files_[index];
  // Until the first slice's size is known there is nothing to compare a header with.
  const cv::Mat image =
      read_image(path, file_bytes_, info_, info_.width == 0 ? std::string() : files_[0]);

  if (image.channels() != 1) {
    throw Error(path, "colour image (" + std::to_string(image.channels()) +
                          " channels): convert to grayscale first");
  }
  if (info_.width == 0) {  // the first slice, whose header could not be read
    SampleType type;
    if (!to_sample_type(image.depth(), &type)) {
      throw Error(path, "image is " + depth_text(image.depth()) +
                            ", expected 8-bit or 16-bit integer samples");
    }
    info_.width = static_cast<std::uint32_t>(image.cols);
    info_.height = static_cast<std::uint32_t>(image.rows);
    info_.type = type;
    row_bytes_ = static_cast<std::size_t>(image.cols) * sample_bytes(type);
  } else {
    if (image.cols != static_cast<int>(info_.width) ||
        image.rows != static_cast<int>(info_.height)) {
      throw Error(path,
                  "image is " + size_text(image.cols, image.rows) + ", expected " +
                      size_text(static_cast<int>(info_.width), static_cast<int>(info_.height)) +
                      " like the first slice (" + files_[0] + ")");
    }
    if (image.depth() != to_cv_depth(info_.type)) {
      throw Error(path, "image is " + depth_text(image.depth()) + ", expected " +
                            depth_text(to_cv_depth(info_.type)) + " like the first slice (" +
                            files_[0] + ")");
    }
  }

  if (buffer_.empty())
    resize_buffer(buffer_, std::uint64_t{row_bytes_} * info_.height, path, "a slice");
  // Copy row by row: a decoded Mat may pad its rows, and reusing buffer_ keeps the slice at one
  // address for the whole run.
  for (int y = 0; y < image.rows; ++y) {
    std::memcpy(buffer_.data() + static_cast<std::size_t>(y) * row_bytes_, image.ptr(y),
                row_bytes_);
  }
  loaded_index_ = index;
}

bool ImageStackSource::next_slice(SliceView* slice) {
  if (next_index_ >= files_.size()) return false;
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
