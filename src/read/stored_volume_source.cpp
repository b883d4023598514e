#include "read/stored_volume_source.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <system_error>
#include <utility>

#include "error.h"
#include "message_line.h"
#include "read/buffer_allocation.h"
#include "read/compression_bounds.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

// Signed bytes to 16-bit samples in place: `bytes` holds `count` int8 samples at its start and
// has room for `count` int16 samples. Backwards, so that no sample is overwritten before it is
// read (sample i moves from byte i to bytes 2i, 2i+1, never below i).
void widen_i8_to_i16(unsigned char* bytes, std::size_t count) {
  for (std::size_t i = count; i-- > 0;) {
    const auto value = static_cast<std::int16_t>(static_cast<std::int8_t>(bytes[i]));
    std::memcpy(bytes + 2 * i, &value, 2);
  }
}

// Stored samples (native order, `count` of them at the start of `bytes`) to the engine's f32,
// times `slope` plus `intercept`, in place: `bytes` has room for both. Samples no wider than a
// float move up, so they go backwards; f64 moves down, so forwards. Either way no sample is
// overwritten before it is read.
template <class Stored>
void to_f32(unsigned char* bytes, std::size_t count, double slope, double intercept) {
  auto convert = [&](std::size_t i) {
    Stored stored;
    std::memcpy(&stored, bytes + i * sizeof(Stored), sizeof(Stored));
    const double value = slope == 1 && intercept == 0
                             ? static_cast<double>(stored)
                             : slope * static_cast<double>(stored) + intercept;
    // Beyond float's range the conversion is undefined: those samples become infinities.
    constexpr double kLargest = std::numeric_limits<float>::max();
    const float sample = value > kLargest    ? std::numeric_limits<float>::infinity()
                         : value < -kLargest ? -std::numeric_limits<float>::infinity()
                                             : static_cast<float>(value);
    std::memcpy(bytes + i * sizeof(float), &sample, sizeof(float));
  };
  if (sizeof(Stored) <= sizeof(float)) {
    for (std::size_t i = count; i-- > 0;) convert(i);
  } else {
    for (std::size_t i = 0; i < count; ++i) convert(i);
  }
}

void convert_to_f32(StoredSample stored, unsigned char* bytes, std::size_t count, double slope,
                    double intercept) {
  switch (stored) {
    case StoredSample::u8: return to_f32<std::uint8_t>(bytes, count, slope, intercept);
    case StoredSample::i8: return to_f32<std::int8_t>(bytes, count, slope, intercept);
    case StoredSample::u16: return to_f32<std::uint16_t>(bytes, count, slope, intercept);
    case StoredSample::i16: return to_f32<std::int16_t>(bytes, count, slope, intercept);
    case StoredSample::f32: return to_f32<float>(bytes, count, slope, intercept);
    case StoredSample::i32: return to_f32<std::int32_t>(bytes, count, slope, intercept);
    case StoredSample::u32: return to_f32<std::uint32_t>(bytes, count, slope, intercept);
    case StoredSample::f64: return to_f32<double>(bytes, count, slope, intercept);
  }
}

// The slice buffer holds the stored samples, then the engine's in place (f64 is the wider of the
// two, narrower samples widen to f32 or i16).
std::uint64_t slice_buffer_bytes(const StoredVolume& volume) {
  return std::max<std::uint64_t>(
      stored_slice_bytes(volume),
      std::uint64_t{volume.info.width} * volume.info.height * sample_bytes(volume.info.type));
}

}  // namespace

StoredVolumeSource::StoredVolumeSource(const StoredVolume& volume, StoredVolumeData data,
                                       const RawFile* same_file_as)
    : volume_(volume),
      data_(std::move(data)),
      file_(data_.path, "a raw sample file", same_file_as),
      end_index_(volume.info.depth) {
  if (volume_.compression == Compression::none) {
    check_raw_size();
  } else {
    check_compressed_size();
  }
}

std::uint64_t StoredVolumeSource::working_bytes() const {
  const std::uint64_t slice = slice_buffer_bytes(volume_);
  // zlib's input buffer, a buffer to measure the stream into, and zlib's state and window.
  constexpr std::uint64_t kInflateBytes = 64 * 1024 + 64 * 1024 + 48 * 1024;
  return slice + (volume_.compression == Compression::none ? 0 : kInflateBytes);
}

std::string StoredVolumeSource::volume_text() const {
  std::string text = "a " + stored_volume_text(volume_) + " volume";
  if (!data_.header.empty() && data_.header != data_.path) text += " (" + data_.header + ")";
  return text;
}

void StoredVolumeSource::check_raw_size() {
  const std::uint64_t needed = stored_volume_bytes(volume_);
  const std::uint64_t size = file_.size_bytes();
  // Sizes and offsets come from the header, so the additions are checked, not trusted.
  if (data_.offset > size || size - data_.offset < needed) {
    const bool overflows = data_.offset > ~std::uint64_t{0} - needed;
    throw Error(data_.path,
                "file is " + std::to_string(size) + " bytes, expected at least " +
                    (overflows ? std::to_string(data_.offset) + " + " + std::to_string(needed)
                               : std::to_string(data_.offset + needed)) +
                    " for " + volume_text() + " starting at byte " + std::to_string(data_.offset));
  }
  if (data_.at_end) data_.offset = size - needed;
}

void StoredVolumeSource::check_compressed_size() {
  const std::uint64_t size = file_.size_bytes();
  if (data_.offset > size) {
    throw Error(data_.path, "file is " + std::to_string(size) +
                                " bytes, but its compressed data should start at byte " +
                                std::to_string(data_.offset));
  }
  std::uint64_t end = size;
  if (data_.compressed_bytes != 0) {
    if (size - data_.offset < data_.compressed_bytes) {
      throw Error(data_.path, "file is " + std::to_string(size) + " bytes, expected at least " +
                                  std::to_string(data_.offset + data_.compressed_bytes) + " for " +
                                  std::to_string(data_.compressed_bytes) +
                                  " bytes of compressed data starting at byte " +
                                  std::to_string(data_.offset));
    }
    end = data_.offset + data_.compressed_bytes;
  }
  const std::uint64_t needed = data_.skip_decompressed + stored_volume_bytes(volume_);
  if (needed < data_.skip_decompressed) throw Error(data_.path, "byte skip is too large");
  // A lying header, or a file cut short: refused before a byte is decompressed.
  if (!could_decode_to(end - data_.offset, kDeflateMaxRatio, needed)) {
    throw Error(data_.path, "its " + std::to_string(end - data_.offset) +
                                " bytes of compressed data cannot hold the " +
                                std::to_string(needed) + " bytes of " + volume_text() +
                                " (deflate expands at most 1032 to 1)");
  }

  // A single gzip member that records the expected size is taken at its word; everything else
  // (zlib, several members, a truncated file whose last bytes are not a trailer) is measured by
  // decompressing once, so that a short stream is refused before extraction starts.
  const std::optional<std::uint32_t> trailer = gzip_trailer_size(file_, data_.offset, end);
  if (!trailer || *trailer != static_cast<std::uint32_t>(needed)) {
    InflateReader measure(file_, data_.offset, end);
    const std::uint64_t available = measure.discard(needed);
    if (available < needed) {
      throw Error(data_.path, "compressed data hold " + std::to_string(available) +
                                  " bytes, expected " + std::to_string(needed) + " for " +
                                  volume_text());
    }
  }
  inflate_ = std::make_unique<InflateReader>(file_, data_.offset, end);
  if (inflate_->discard(data_.skip_decompressed) != data_.skip_decompressed) {
    throw Error(data_.path, "compressed data end within the " +
                                std::to_string(data_.skip_decompressed) + " bytes to skip");
  }
}

std::unique_ptr<SliceSource> StoredVolumeSource::open_range(std::uint32_t first,
                                                            std::uint32_t end) const {
  // Opens the data file again and checks its size again, as a reader of its own.
  auto range = std::make_unique<StoredVolumeSource>(volume_, data_, &file_);
  range->next_index_ = first;
  range->end_index_ = end;
  return range;
}

void StoredVolumeSource::check_exact_in_float(const unsigned char* bytes, std::size_t count) const {
  constexpr std::int64_t kExact = std::int64_t{1} << 24;  // floats hold every integer up to it
  for (std::size_t i = 0; i < count; ++i) {
    std::int64_t value;
    if (volume_.stored == StoredSample::i32) {
      std::int32_t v;
      std::memcpy(&v, bytes + 4 * i, 4);
      value = v;
    } else {
      std::uint32_t v;
      std::memcpy(&v, bytes + 4 * i, 4);
      value = v;
    }
    if (value > kExact || value < -kExact)
      throw Error(data_.path, "slice " + std::to_string(next_index_) + " holds " +
                                  std::to_string(value) +
                                  ", beyond 16777216: 32-bit integers become floats, which hold "
                                  "whole numbers exactly only up to that (labels would merge)");
  }
}

bool StoredVolumeSource::next_slice(SliceView* slice) {
  if (next_index_ >= end_index_) return false;
  const std::size_t stored_bytes = static_cast<std::size_t>(stored_slice_bytes(volume_));
  if (buffer_.empty()) resize_buffer(buffer_, slice_buffer_bytes(volume_), data_.path, "a slice");
  if (inflate_) {
    inflate_->read(buffer_.data(), stored_bytes,
                   data_.skip_decompressed + stored_volume_bytes(volume_), volume_text());
  } else {
    file_.read_at(data_.offset + std::uint64_t{next_index_} * stored_bytes, buffer_.data(),
                  stored_bytes);
  }
  const std::size_t bytes_per_sample = stored_sample_bytes(volume_.stored);
  const std::size_t samples = stored_bytes / bytes_per_sample;
  swap_to_native(buffer_.data(), samples, bytes_per_sample, volume_.byte_order);
  if (volume_.info.type == SampleType::f32) {
    if ((volume_.stored == StoredSample::i32 || volume_.stored == StoredSample::u32) &&
        !volume_.scaled())
      check_exact_in_float(buffer_.data(), samples);
    if (volume_.stored != StoredSample::f32 || volume_.scaled())
      convert_to_f32(volume_.stored, buffer_.data(), samples, volume_.scale_slope,
                     volume_.scale_intercept);
  } else if (volume_.stored == StoredSample::i8) {
    widen_i8_to_i16(buffer_.data(), samples);
  }

  slice->samples = buffer_.data();
  slice->width = volume_.info.width;
  slice->height = volume_.info.height;
  slice->row_stride_bytes =
      static_cast<std::size_t>(volume_.info.width) * sample_bytes(volume_.info.type);
  slice->type = volume_.info.type;
  ++next_index_;
  return true;
}

std::string read_file_start(RawFile& file, std::size_t max_bytes,
                            bool (*complete)(const std::string& text)) {
  const std::size_t limit =
      static_cast<std::size_t>(std::min<std::uint64_t>(file.size_bytes(), max_bytes));
  std::size_t wanted = complete ? std::min<std::size_t>(limit, 64 * 1024) : limit;
  std::string text;
  for (;;) {
    const std::size_t had = text.size();
    text.resize(wanted);
    file.read_at(had, text.data() + had, wanted - had);
    if (wanted == limit || complete(text)) return text;
    wanted = std::min(limit, 4 * wanted);
  }
}

std::string resolve_data_file(const std::string& header_path, const std::string& data_file) {
  fs::path path(data_file);
  if (path.is_relative()) path = fs::path(header_path).parent_path() / path;
  // The name comes from the header, whatever bytes it holds (a NUL among them): shown escaped.
  const std::string shown = one_line(path.string());
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) {
    throw Error(header_path, "data file " + shown + " does not exist");
  }
  if (fs::is_directory(status)) {
    throw Error(header_path, "data file " + shown + " is a directory");
  }
  // Opening a FIFO waits for a writer, forever if none comes; and a header's offsets and sizes
  // mean nothing in a stream. (A raw volume may still be a pipe: there the user says so.)
  if (!fs::is_regular_file(status)) {
    const char* kind = fs::is_fifo(status)     ? "a FIFO"
                       : fs::is_socket(status) ? "a socket"
                                               : "a device";
    throw Error(header_path, "data file " + shown + " is " + kind + ", not a regular file");
  }
  return path.string();
}

}  // namespace mvox
