#include "read/raw/raw_volume_source.h"

#include "error.h"
#include "read/buffer_allocation.h"

namespace mvox {

namespace {

const RawFormat& volume_format(const RawFormat& format) {
  if (format.depth == 0) {
    throw Error("--raw", raw_format_text(format) +
                             " describes one file per slice; one volume file needs WxHxD:TYPE");
  }
  return format;
}

}  // namespace

RawVolumeSource::RawVolumeSource(const std::string& path, const RawFormat& format)
    : RawVolumeSource(path, volume_format(format), 0, format.depth, nullptr) {
  file_.expect_size(std::uint64_t{format_.depth} * format_.slice_bytes(),
                    "a " + raw_format_text(format_) + " volume");
}

RawVolumeSource::RawVolumeSource(const std::string& path, const RawFormat& format,
                                 std::uint32_t first, std::uint32_t end,
                                 const RawFile* same_file_as)
    : file_(path, "a raw sample file", same_file_as),
      format_(format),
      slices_(file_, std::uint64_t{first} * format.slice_bytes(), format.slice_bytes(), end - first,
              kChunkBytes),
      next_index_(first),
      end_index_(end) {
  info_.width = format_.width;
  info_.height = format_.height;
  info_.depth = format_.depth;
  info_.type = format_.type;
}

std::unique_ptr<SliceSource> RawVolumeSource::open_range(std::uint32_t first,
                                                         std::uint32_t end) const {
  return std::unique_ptr<SliceSource>(
      new RawVolumeSource(file_.path(), format_, first, end, &file_));
}

bool RawVolumeSource::next_slice(SliceView* slice) {
  if (next_index_ >= end_index_) {
    // A pipe's size was not known up front: a longer stream is as wrong as a longer file.
    if (next_index_ == format_.depth) {
      file_.expect_end(std::uint64_t{format_.depth} * format_.slice_bytes(),
                       "a " + raw_format_text(format_) + " volume");
      ++next_index_;
    }
    return false;
  }
  *slice = native_slice_view(slices_.next(), format_);
  ++next_index_;
  return true;
}

}  // namespace mvox
