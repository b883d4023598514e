#include "read/raw/raw_slices_source.h"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <system_error>
#include <utility>

#include "error.h"
#include "read/buffer_allocation.h"
#include "read/raw_file.h"

namespace mvox {

RawSlicesSource::RawSlicesSource(std::vector<std::string> paths, const RawFormat& format)
    : files_(std::make_shared<const std::vector<std::string>>(std::move(paths))), format_(format) {
  if (format_.depth != 0) {
    throw Error("--raw", raw_format_text(format_) +
                             " describes one volume file; one file per slice needs WxH:TYPE");
  }
  if (files().empty()) throw Error("INPUT", "no raw slice files");
  if (files().size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("INPUT", "more than 2^32-1 slice files");
  }
  const std::string what = "one " + raw_format_text(format_) + " slice";
  for (const std::string& path : files()) {
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    if (error) throw Error(path, "cannot get file size: " + error.message());
    if (size != format_.slice_bytes()) {
      throw Error(path, raw_size_problem(size, format_.slice_bytes(), what));
    }
  }
  info_.width = format_.width;
  info_.height = format_.height;
  info_.depth = static_cast<std::uint32_t>(files().size());
  info_.type = format_.type;
}

std::unique_ptr<SliceSource> RawSlicesSource::open_range(std::uint32_t first,
                                                         std::uint32_t end) const {
  auto range = std::make_unique<RawSlicesSource>(*this);  // the file list, no file open
  range->buffer_ = {};
  range->next_index_ = first;
  range->end_index_ = end;
  return range;
}

bool RawSlicesSource::next_slice(SliceView* slice) {
  if (next_index_ >= std::min(files().size(), end_index_)) return false;
  RawFile file(files()[next_index_], "a raw sample file", nullptr, FileKinds::only_regular);
  // Checked again at read time: the file may have changed since the constructor looked.
  file.expect_size(format_.slice_bytes(), "one " + raw_format_text(format_) + " slice");
  if (buffer_.empty()) resize_buffer(buffer_, format_.slice_bytes(), file.name(), "a slice");
  file.read_at(0, buffer_.data(), buffer_.size());
  *slice = native_slice_view(buffer_.data(), format_);
  ++next_index_;
  return true;
}

}  // namespace mvox
