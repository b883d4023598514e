#include "read/tiff/tiff_stack_source.h"

#include <sys/stat.h>
#include <tiff.h>  // TIFF's tag values, by name; libtiff itself is the TIFF module's (tiff_file.h)

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <new>
#include <utility>

#include "error.h"
#include "read/compression_bounds.h"
#include "read/header_text.h"
#include "read/tiff/tiff_file.h"
#include "read/tiff/tiff_predictor.h"

namespace mvox {

namespace {

// What a page holds, as far as the stack cares.
struct PageFormat {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  SampleType type = SampleType::u8;
  mvox_tiff_page tags{};  // every tag mvox reads, compression among them (not the stack's format)
};

std::string sample_text(SampleType type) {
  switch (type) {
    case SampleType::u8: return "8-bit unsigned";
    case SampleType::u16: return "16-bit unsigned";
    case SampleType::i16: return "16-bit signed";
    case SampleType::f32: return "32-bit float";
  }
  return "?";
}

std::string page_subject(std::uint64_t page_index) {
  return "page " + std::to_string(page_index + 1);
}

// Reads and checks the current directory's format. Refusals name the page (1-based).
PageFormat page_format(TiffFile& tiff, std::uint64_t page_index) {
  const std::string page = page_subject(page_index);
  PageFormat format;
  format.tags = tiff.tags();
  format.width = format.tags.width;
  format.height = format.tags.height;
  const std::uint16_t samples_per_pixel = format.tags.samples_per_pixel;
  const std::uint16_t bits = format.tags.bits_per_sample;
  const std::uint16_t sample_format = format.tags.sample_format;
  // A missing photometric tag reads as min-is-black, as most readers do.
  const std::uint16_t photometric = format.tags.photometric;
  const std::uint16_t compression = format.tags.compression;

  if (format.width == 0 || format.height == 0) {
    throw Error(tiff.path(), page + " has no pixels (" + std::to_string(format.width) + "x" +
                                 std::to_string(format.height) + ")");
  }
  if (photometric == PHOTOMETRIC_PALETTE) {
    throw Error(tiff.path(), page + " is a palette colour image: convert to grayscale first");
  }
  if (samples_per_pixel != 1 ||
      (photometric != PHOTOMETRIC_MINISBLACK && photometric != PHOTOMETRIC_MINISWHITE)) {
    throw Error(tiff.path(), page + " is a colour or multi-sample image (" +
                                 std::to_string(samples_per_pixel) +
                                 " samples per pixel, photometric " + std::to_string(photometric) +
                                 "): convert to grayscale first");
  }
  if (photometric == PHOTOMETRIC_MINISWHITE) {
    throw Error(tiff.path(), page +
                                 " is min-is-white (0 is white): invert it to min-is-black "
                                 "first, so that higher values are denser");
  }
  if (bits == 8 && sample_format == SAMPLEFORMAT_UINT) {
    format.type = SampleType::u8;
  } else if (bits == 16 && sample_format == SAMPLEFORMAT_UINT) {
    format.type = SampleType::u16;
  } else if (bits == 16 && sample_format == SAMPLEFORMAT_INT) {
    format.type = SampleType::i16;
  } else if (bits == 32 && sample_format == SAMPLEFORMAT_IEEEFP) {
    format.type = SampleType::f32;
  } else {
    const char* kind = sample_format == SAMPLEFORMAT_UINT     ? "unsigned"
                       : sample_format == SAMPLEFORMAT_INT    ? "signed"
                       : sample_format == SAMPLEFORMAT_IEEEFP ? "float"
                                                              : "other";
    throw Error(tiff.path(), page + " has " + std::to_string(bits) + "-bit " + kind +
                                 " samples: mvox reads 8-bit unsigned, 16-bit unsigned or signed, "
                                 "and 32-bit float");
  }
  if (!format.tags.codec_configured) {
    throw Error(tiff.path(), page + " uses compression " + std::to_string(compression) +
                                 ", which this libtiff cannot decode");
  }
  return format;
}

// Sizes from a header can be anything up to 2^32 per side: their products saturate at the
// largest uint64 instead of wrapping round to a small, harmless-looking size.
std::uint64_t product(std::uint64_t a, std::uint64_t b) {
  std::uint64_t result;
  return __builtin_mul_overflow(a, b, &result) ? std::numeric_limits<std::uint64_t>::max() : result;
}

std::uint64_t sum(std::uint64_t a, std::uint64_t b) {
  std::uint64_t result;
  return __builtin_add_overflow(a, b, &result) ? std::numeric_limits<std::uint64_t>::max() : result;
}

std::uint64_t slice_bytes(const VolumeInfo& info) {
  return product(product(info.width, info.height), sample_bytes(info.type));
}

bool is_deflate(std::uint16_t compression) {
  return compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE;
}

// How far a codec's stored bytes can expand (compression_bounds.h).
struct CodecBound {
  const char* name;
  std::uint64_t max_ratio;  // 1: uncompressed, exactly; 0: no bound known
};

CodecBound codec_bound(std::uint16_t compression) {
  switch (compression) {
    case COMPRESSION_NONE: return {"uncompressed", 1};
    case COMPRESSION_ADOBE_DEFLATE:
    case COMPRESSION_DEFLATE: return {"deflate", kDeflateMaxRatio};
    case COMPRESSION_LZW: return {"LZW", kLzwMaxRatio};
    case COMPRESSION_PACKBITS: return {"PackBits", kPackBitsMaxRatio};
    // TIFF's JPEG (technical note 2) is baseline in practice; an arithmetic-coded or
    // progressive one squeezed beyond the baseline bound would be refused.
    case COMPRESSION_JPEG: return {"JPEG", kJpegBaselineMaxRatio};
    default: return {"", 0};  // LZMA, Zstandard, WebP, JPEG XL, ...: the memory budget's
  }
}

// True when `stored` bytes of data compressed with `codec` can hold `decoded` bytes.
bool could_hold(const CodecBound& codec, std::uint64_t stored, std::uint64_t decoded) {
  if (codec.max_ratio == 0) return true;
  // Uncompressed data are the samples themselves: libtiff fails on fewer bytes anyway.
  if (codec.max_ratio == 1) return decoded <= stored;
  return could_decode_to(stored, codec.max_ratio, decoded);
}

// " but stores N bytes of CODEC data[, which decode to at most R times as many]".
std::string stored_text(const CodecBound& codec, std::uint64_t stored) {
  std::string text = " but stores " + std::to_string(stored) + " bytes of " + codec.name + " data";
  if (codec.max_ratio > 1) {
    text += ", which decode to at most " + std::to_string(codec.max_ratio) + " times as many";
  }
  return text;
}

// TIFF tiles are multiples of 16 on each side, and writers pick one tile size whatever the
// image (256 or 512 mostly, up to 4096 for large scans), so a tile of a small image may reach
// far beyond it. But a tile never needs more than the whole image rounded up to multiples of
// 16, nor than 4096x4096 samples: anything larger is a lying header, whose tile buffer alone
// could take gigabytes for a tiny image.
constexpr std::uint64_t kLargestFixedTileSamples = 4096 * 4096;

std::uint64_t round_up_16(std::uint64_t n) { return (n + 15) / 16 * 16; }

// What reading a page takes, from its directory.
struct PageBuffers {
  std::uint64_t tile = 0;           // one decoded tile, for tiled pages
  std::uint64_t largest_chunk = 0;  // stored bytes of its largest strip or tile
};

// Refuses a page whose strips or tiles do not lie inside the file (the file was cut short),
// or declare more decoded bytes than their stored bytes can hold, alone or all together, and
// tiles far larger than the image. `format` is the page's, checked already.
PageBuffers check_page_data(TiffFile& tiff, std::uint64_t page_index, std::uint64_t file_bytes,
                            const PageFormat& format) {
  const std::string page = page_subject(page_index);
  const bool tiled = format.tags.tiled != 0;
  const std::string samples_text = " " + sample_text(format.type) + " samples";
  const std::uint64_t bytes_per_sample = sample_bytes(format.type);
  const std::uint64_t row_bytes = std::uint64_t{format.width} * bytes_per_sample;
  const CodecBound codec = codec_bound(format.tags.compression);
  PageBuffers buffers;

  std::uint32_t tile_width = 0, tile_height = 0, rows_per_strip = format.height;
  if (tiled) {
    tile_width = format.tags.tile_width;
    tile_height = format.tags.tile_height;
    const std::uint64_t tile_samples = std::uint64_t{tile_width} * tile_height;
    if (tile_samples == 0) {
      throw Error(tiff.path(), page + ": invalid tile size " + std::to_string(tile_width) + "x" +
                                   std::to_string(tile_height));
    }
    const std::uint64_t image_samples =
        product(round_up_16(format.width), round_up_16(format.height));
    if (tile_samples > std::max(image_samples, kLargestFixedTileSamples)) {
      throw Error(tiff.path(), page + ": its " + std::to_string(tile_width) + "x" +
                                   std::to_string(tile_height) + " tiles are far larger than the " +
                                   std::to_string(format.width) + "x" +
                                   std::to_string(format.height) +
                                   " image (a tile may hold the image rounded up to multiples of "
                                   "16, or 4096x4096 samples)");
    }
    buffers.tile = product(tile_samples, bytes_per_sample);
  } else {
    rows_per_strip = format.tags.rows_per_strip;
    if (rows_per_strip == 0 || rows_per_strip > format.height) rows_per_strip = format.height;
  }

  const std::uint32_t count = format.tags.chunks;
  std::uint64_t stored_total = 0, decoded_total = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string chunk = (tiled ? "tile " : "strip ") + std::to_string(i);
    std::uint64_t offset = 0, bytes = 0;
    if (!tiff.chunk_location(i, &offset, &bytes) || bytes == 0) {
      throw Error(tiff.path(), page + ": " + chunk + " has no data" + tiff.take_error());
    }
    if (offset > file_bytes || file_bytes - offset < bytes) {
      throw Error(tiff.path(), page + ": " + chunk + " ends at byte " +
                                   std::to_string(offset + bytes) + ", but the file is " +
                                   std::to_string(file_bytes) + " bytes (truncated)");
    }
    // A strip holds rows_per_strip rows, the last one what is left; a tile is whole even
    // where it reaches past the image.
    std::uint64_t decoded = buffers.tile;
    std::string declared = std::to_string(tile_width) + "x" + std::to_string(tile_height);
    if (!tiled) {
      const std::uint64_t first_row = std::uint64_t{i} * rows_per_strip;
      const std::uint64_t rows =
          first_row >= format.height
              ? 0
              : std::min<std::uint64_t>(rows_per_strip, format.height - first_row);
      decoded = product(rows, row_bytes);
      declared = std::to_string(rows) + " rows of " + std::to_string(format.width);
    }
    if (!could_hold(codec, bytes, decoded)) {
      throw Error(tiff.path(), page + ": " + chunk + " declares " + std::to_string(decoded) +
                                   " bytes (" + declared + samples_text + ")" +
                                   stored_text(codec, bytes));
    }
    stored_total = sum(stored_total, bytes);
    decoded_total = sum(decoded_total, decoded);
    buffers.largest_chunk = std::max(buffers.largest_chunk, bytes);
  }
  // Many small strips or tiles, each within its codec's allowance for a stream's overhead,
  // must not add up to a page that the file cannot hold either.
  if (!could_hold(codec, stored_total, decoded_total)) {
    throw Error(tiff.path(), page + " declares " + std::to_string(decoded_total) + " bytes (" +
                                 std::to_string(format.width) + "x" +
                                 std::to_string(format.height) + samples_text + ") in " +
                                 std::to_string(count) + (tiled ? " tiles" : " strips") +
                                 stored_text(codec, stored_total));
  }
  return buffers;
}

// Resizes `buffer` to at least `bytes`; a failed allocation is an mvox::Error naming the file,
// the bytes and `what` they were for, never a bare std::bad_alloc.
void grow_buffer(ReadBuffer& buffer, std::uint64_t bytes, const std::string& path,
                 const std::string& what) {
  if (buffer.size() >= bytes) return;
  try {
    if (bytes > buffer.max_size()) throw std::bad_alloc();
    buffer.resize(static_cast<std::size_t>(bytes));
  } catch (const std::bad_alloc&) {
    throw Error(path,
                "out of memory: cannot allocate " + std::to_string(bytes) + " bytes for " + what);
  }
}

std::uint64_t file_size(const std::string& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) throw Error(path, "cannot stat: " + errno_text(errno));
  return static_cast<std::uint64_t>(status.st_size);
}

bool same_format(const PageFormat& a, const PageFormat& b) {
  return a.width == b.width && a.height == b.height && a.type == b.type;
}

// ImageJ writes stacks with "ImageJ=1.x\nimages=N\nslices=N\nunit=mm\nspacing=2.5\n..." in the
// ImageDescription and the pixel size as XResolution/YResolution (pixels per unit).
void read_imagej_spacing(const mvox_tiff_page& tags, VolumeInfo& info) {
  if (!tags.description) return;
  const std::string_view text(tags.description);
  if (text.substr(0, 7) != "ImageJ=") return;
  double z_spacing = 0;
  bool found = false;
  for (const HeaderLine& line : split_header_lines(text, nullptr)) {
    if (line.text.substr(0, 8) == "spacing=") {
      found = parse_real(trim(line.text.substr(8)), false, &z_spacing) && z_spacing > 0;
    }
  }
  if (!found) return;
  info.spacing[2] = z_spacing;
  if (tags.x_resolution > 0 && std::isfinite(1.0 / tags.x_resolution)) {
    info.spacing[0] = 1.0 / tags.x_resolution;
  }
  if (tags.y_resolution > 0 && std::isfinite(1.0 / tags.y_resolution)) {
    info.spacing[1] = 1.0 / tags.y_resolution;
  }
}

}  // namespace

TiffStackSource::TiffStackSource(std::vector<std::string> files) : files_(std::move(files)) {
  if (files_.empty()) throw Error("INPUT", "no TIFF files");
  std::uint64_t pages = 0;
  for (std::size_t i = 0; i < files_.size(); ++i) check_file(i, &pages);
  if (pages > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("INPUT", "more than 2^32-1 TIFF pages");
  }
  info_.depth = static_cast<std::uint32_t>(pages);
  // No buffer yet: they come with the first slice (next_slice), after every directory has
  // been checked, and so after every refusal that needs no decoding.
}

std::uint64_t TiffStackSource::working_bytes() const {
  const std::uint64_t slice = slice_bytes(info_);
  // libtiff reads a stored strip or tile into a buffer rounded up to 1 KiB (TIFFReadBufferSetup);
  // uncompressed ones go straight into mvox's buffers.
  const std::uint64_t libtiff_raw = (largest_libtiff_chunk_ + 1023) / 1024 * 1024;
  const std::uint64_t deflate =
      largest_deflate_chunk_ == 0 ? 0 : largest_deflate_chunk_ + ZlibStreamCheck::kWorkingBytes;
  return sum(sum(slice, largest_tile_), sum(libtiff_raw, deflate));
}

TiffStackSource::~TiffStackSource() = default;

void TiffStackSource::check_file(std::size_t file_index, std::uint64_t* pages) {
  TiffFile tiff(files_[file_index]);
  const std::uint64_t bytes = file_size(tiff.path());
  std::uint64_t page = 0;
  for (;;) {
    const PageFormat format = page_format(tiff, page);
    if (file_index == 0 && page == 0) {
      info_.width = format.width;
      info_.height = format.height;
      info_.type = format.type;
      read_imagej_spacing(format.tags, info_);
    } else {
      const PageFormat first{info_.width, info_.height, info_.type};
      if (!same_format(format, first)) {
        const std::string like = file_index == 0 ? "page 1" : "page 1 of " + files_[0];
        throw Error(tiff.path(), page_subject(page) + " is " + std::to_string(format.width) + "x" +
                                     std::to_string(format.height) + " " +
                                     sample_text(format.type) + ", expected " +
                                     std::to_string(first.width) + "x" +
                                     std::to_string(first.height) + " " + sample_text(first.type) +
                                     " like " + like);
      }
    }
    const PageBuffers buffers = check_page_data(tiff, page, bytes, format);
    largest_tile_ = std::max(largest_tile_, buffers.tile);
    if (is_deflate(format.tags.compression)) {
      largest_deflate_chunk_ = std::max(largest_deflate_chunk_, buffers.largest_chunk);
    } else if (format.tags.compression != COMPRESSION_NONE) {
      largest_libtiff_chunk_ = std::max(largest_libtiff_chunk_, buffers.largest_chunk);
    }
    ++page;
    tiff.take_error();
    if (!tiff.read_directory()) {
      // false both at the last page and on a broken directory; only the latter reports an error.
      const std::string error = tiff.take_error();
      if (!error.empty()) {
        throw Error(tiff.path(),
                    "cannot read the directory of page " + std::to_string(page + 1) + error);
      }
      break;
    }
  }
  pages_per_file_.push_back(page);
  *pages += page;
}

bool TiffStackSource::read_chunk(const mvox_tiff_page& tags, std::uint32_t index, bool deflate,
                                 unsigned char* out, std::size_t out_bytes,
                                 std::size_t row_samples) {
  TiffFile& tiff = *open_;
  if (!deflate) return tiff.read_chunk(index, out, out_bytes);
  // libtiff's deflate decoder stops once it has the samples, often before the zlib checksum:
  // the stored bytes are read here and inflated whole, checksum included (zlib_stream_check.h).
  const std::string chunk = page_subject(page_in_file_) + ": " + (tags.tiled ? "tile " : "strip ") +
                            std::to_string(index);
  std::uint64_t offset = 0, stored = 0;
  if (!tiff.chunk_location(index, &offset, &stored)) return false;
  // The constructor saw every strip and tile; the file may have changed since.
  if (stored > largest_deflate_chunk_) {
    throw Error(tiff.path(), chunk + " changed since the stack was opened");
  }
  grow_buffer(raw_, stored, tiff.path(), "the stored data of " + chunk);
  if (!tiff.read_stored_chunk(index, raw_.data(), stored)) {
    throw Error(tiff.path(), chunk + ": cannot read its " + std::to_string(stored) + " bytes" +
                                 tiff.take_error());
  }
  // Bits stored in reverse order (FillOrder 2) are put right before inflating, as libtiff
  // does.
  const bool reversed = tags.fill_order == FILLORDER_LSB2MSB;
  if (reversed) reverse_bit_order(raw_.data(), static_cast<std::size_t>(stored));
  if (!deflate_check_) deflate_check_ = std::make_unique<ZlibStreamCheck>();
  ZlibStreamCheck::Result inflated;
  try {
    inflated =
        deflate_check_->inflate(raw_.data(), static_cast<std::size_t>(stored), out, out_bytes);
  } catch (const std::bad_alloc&) {
    throw Error(tiff.path(), "out of memory: cannot allocate zlib's state (about " +
                                 std::to_string(ZlibStreamCheck::kWorkingBytes) + " bytes)");
  }
  if (!inflated.problem.empty()) {
    throw Error(tiff.path(), chunk + ": corrupt deflate data (zlib: " + inflated.problem + ")");
  }
  if (inflated.total < out_bytes) {
    throw Error(tiff.path(), chunk + ": its deflate data decode to " +
                                 std::to_string(inflated.total) + " bytes, fewer than the " +
                                 std::to_string(out_bytes) + " it holds");
  }
  // What libtiff does after inflating: byte order and predictor.
  const std::size_t bytes_per_sample = sample_bytes(info_.type);
  if (finish_tiff_samples(out, out_bytes / (row_samples * bytes_per_sample), row_samples,
                          bytes_per_sample, tags.byte_swapped != 0, tags.predictor)) {
    return true;
  }
  // The floating-point predictor: libtiff decodes the checked bytes once more, from this buffer
  // (with their bits back in stored order, which it reverses itself).
  if (reversed) reverse_bit_order(raw_.data(), static_cast<std::size_t>(stored));
  return tiff.decode_stored_chunk(index, raw_.data(), stored, out, out_bytes);
}

void TiffStackSource::read_page(ReadBuffer& buffer, const mvox_tiff_page& tags) {
  TiffFile& tiff = *open_;
  const std::string page = page_subject(page_in_file_);
  const bool deflate = is_deflate(tags.compression);
  // When libtiff decodes deflate itself (the floating-point predictor, read_chunk), it must not
  // use libdeflate, which can leave the end of a strip unwritten (tiff_codecs_api.h).
  if (deflate && !tiff.inflate_with_zlib()) {
    throw Error(tiff.path(),
                page + ": libtiff cannot decode deflate with zlib" + tiff.take_error());
  }
  const std::size_t bytes_per_sample = sample_bytes(info_.type);
  const std::size_t row_bytes = static_cast<std::size_t>(info_.width) * bytes_per_sample;
  tiff.take_error();

  if (!tags.tiled) {
    std::uint32_t rows_per_strip = tags.rows_per_strip;
    if (rows_per_strip == 0 || rows_per_strip > info_.height) rows_per_strip = info_.height;
    for (std::uint32_t row = 0; row < info_.height; row += rows_per_strip) {
      const std::uint32_t rows = std::min(rows_per_strip, info_.height - row);
      if (!read_chunk(tags, tiff.chunk_at(0, row), deflate, buffer.data() + row * row_bytes,
                      rows * row_bytes, info_.width)) {
        throw Error(tiff.path(), page + ": cannot decode the strip at row " + std::to_string(row) +
                                     tiff.take_error());
      }
    }
    return;
  }

  const std::uint32_t tile_width = tags.tile_width, tile_height = tags.tile_height;
  const std::uint64_t tile_bytes = product(product(tile_width, tile_height), bytes_per_sample);
  // The constructor checked the tile size; the file may have changed since.
  if (tile_width == 0 || tile_height == 0 || tags.tile_bytes < tile_bytes ||
      tile_bytes > largest_tile_) {
    throw Error(tiff.path(), page + ": invalid tile size " + std::to_string(tile_width) + "x" +
                                 std::to_string(tile_height));
  }
  grow_buffer(tile_, tile_bytes, tiff.path(),
              "a " + std::to_string(tile_width) + "x" + std::to_string(tile_height) + " tile");
  for (std::uint32_t y = 0; y < info_.height; y += tile_height) {
    for (std::uint32_t x = 0; x < info_.width; x += tile_width) {
      if (!read_chunk(tags, tiff.chunk_at(x, y), deflate, tile_.data(),
                      static_cast<std::size_t>(tile_bytes), tile_width)) {
        throw Error(tiff.path(), page + ": cannot decode the tile at x " + std::to_string(x) +
                                     ", y " + std::to_string(y) + tiff.take_error());
      }
      // Tiles on the right and bottom edges reach past the image; only their inside is copied.
      const std::uint32_t rows = std::min(tile_height, info_.height - y);
      const std::size_t copy_bytes = std::min(tile_width, info_.width - x) * bytes_per_sample;
      for (std::uint32_t r = 0; r < rows; ++r) {
        std::memcpy(buffer.data() + (y + r) * row_bytes + x * bytes_per_sample,
                    tile_.data() + std::size_t{r} * tile_width * bytes_per_sample, copy_bytes);
      }
    }
  }
}

bool TiffStackSource::next_slice(SliceView* slice) {
  if (next_index_ >= info_.depth) return false;
  if (open_ && page_in_file_ >= pages_per_file_[file_index_]) {
    open_.reset();
    ++file_index_;
  }
  if (!open_) {
    open_ = std::make_unique<TiffFile>(files_[file_index_]);
    page_in_file_ = 0;
  } else {
    open_->take_error();
    if (!open_->read_directory()) {
      throw Error(open_->path(), "cannot read the directory of page " +
                                     std::to_string(page_in_file_ + 1) + open_->take_error());
    }
  }
  // Checked again while streaming: the file may have changed since the constructor looked.
  const PageFormat format = page_format(*open_, page_in_file_);
  if (!same_format(format, PageFormat{info_.width, info_.height, info_.type})) {
    throw Error(open_->path(), page_subject(page_in_file_) + " changed since the stack was opened");
  }
  grow_buffer(buffer_, slice_bytes(info_), open_->path(),
              "the " + std::to_string(info_.width) + "x" + std::to_string(info_.height) + " slice");
  read_page(buffer_, format.tags);

  slice->samples = buffer_.data();
  slice->width = info_.width;
  slice->height = info_.height;
  slice->row_stride_bytes = static_cast<std::size_t>(info_.width) * sample_bytes(info_.type);
  slice->type = info_.type;
  ++page_in_file_;
  ++next_index_;
  return true;
}

bool has_tiff_extension(const std::string& path) {
  const std::string extension = lowercase(std::filesystem::path(path).extension().string());
  return extension == ".tif" || extension == ".tiff";
}

std::uint64_t tiff_page_count(const std::string& path) {
  TiffFile tiff(path);
  std::uint64_t pages = 1;
  while (tiff.read_directory()) ++pages;
  const std::string error = tiff.take_error();
  if (!error.empty()) {
    throw Error(path, "cannot read the directory of page " + std::to_string(pages + 1) + error);
  }
  return pages;
}

}  // namespace mvox
