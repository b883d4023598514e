#include "image_stack_source.h"

#include <cstring>
#include <filesystem>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <utility>

#include "error.h"

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

cv::Mat read_image(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw Error(path, "no such file");
  cv::Mat image;
  try {
    // ANYDEPTH keeps 16-bit samples (the default would scale them to 8 bits); ANYCOLOR keeps
    // the channel count so colour images are detected instead of silently converted.
    image = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  } catch (const cv::Exception& e) {
    throw Error(path, "cannot decode image: " + e.msg);
  }
  if (image.empty()) {
    throw Error(path, "cannot read image (unreadable, corrupt, truncated or not an image format)");
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
  load(0);
}

void ImageStackSource::load(std::size_t index) {
  const std::string& path = files_[index];
  const cv::Mat image = read_image(path);

  if (image.channels() != 1) {
    throw Error(path, "colour image (" + std::to_string(image.channels()) +
                          " channels): convert to grayscale first");
  }
  if (index == 0) {
    SampleType type;
    if (!to_sample_type(image.depth(), &type)) {
      throw Error(path, "image is " + depth_text(image.depth()) +
                            ", expected 8-bit or 16-bit integer samples");
    }
    info_.width = static_cast<std::uint32_t>(image.cols);
    info_.height = static_cast<std::uint32_t>(image.rows);
    info_.type = type;
    row_bytes_ = static_cast<std::size_t>(image.cols) * sample_bytes(type);
    buffer_.resize(row_bytes_ * info_.height);
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
