#include "read/tiff/tiff_stack_source.h"

#include <sys/stat.h>
#include <tiffio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <new>
#include <utility>

#include "error.h"
#include "read/compression_bounds.h"
#include "read/header_text.h"
#include "read/tiff/tiff_predictor.h"

namespace mvox {

// An open TIFF file. libtiff reports problems through callbacks; these handlers, registered
// for this handle only (TIFFOpenExt, libtiff 4.5), keep the first error so that it ends up in
// one mvox::Error line, and drop warnings (unknown tags are common and harmless) instead of
// letting libtiff print them on standard error.
struct TiffStackSource::Tiff {
  TIFF* handle = nullptr;
  std::string path;
  std::string error;  // the first error libtiff reported since the last take_error()

  explicit Tiff(const std::string& file_path);
  ~Tiff() {
    if (handle) TIFFClose(handle);
  }
  Tiff(const Tiff&) = delete;
  Tiff& operator=(const Tiff&) = delete;

  // " (libtiff: MESSAGE)", or "" when libtiff said nothing; clears the error.
  std::string take_error() {
    std::string text = error.empty() ? "" : " (libtiff: " + error + ")";
    error.clear();
    return text;
  }
};

namespace {

int keep_first_error(TIFF*, void* user_data, const char*, const char* format, va_list arguments) {
  auto* tiff = static_cast<TiffStackSource::Tiff*>(user_data);
  if (tiff->error.empty()) {
    char text[512];
    std::vsnprintf(text, sizeof text, format, arguments);
    tiff->error = text;
    // One line, whatever libtiff wrote.
    std::replace(tiff->error.begin(), tiff->error.end(), '\n', ' ');
  }
  return 1;  // handled: libtiff's global handler does not print it
}

int drop_warning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

// What a page holds, as far as the stack cares.
struct PageFormat {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  SampleType type = SampleType::u8;
  std::uint16_t compression = COMPRESSION_NONE;  // not part of the stack's format
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
PageFormat page_format(TiffStackSource::Tiff& tiff, std::uint64_t page_index) {
  TIFF* t = tiff.handle;
  const std::string page = page_subject(page_index);
  PageFormat format;
  std::uint16_t samples_per_pixel = 1, bits = 1, sample_format = SAMPLEFORMAT_UINT;
  std::uint16_t photometric = PHOTOMETRIC_MINISBLACK, compression = COMPRESSION_NONE;
  TIFFGetField(t, TIFFTAG_IMAGEWIDTH, &format.width);
  TIFFGetField(t, TIFFTAG_IMAGELENGTH, &format.height);
  TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLESPERPIXEL, &samples_per_pixel);
  TIFFGetFieldDefaulted(t, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLEFORMAT, &sample_format);
  TIFFGetFieldDefaulted(t, TIFFTAG_COMPRESSION, &compression);
  // A missing photometric tag is read as min-is-black, as most readers do.
  TIFFGetField(t, TIFFTAG_PHOTOMETRIC, &photometric);

  if (format.width == 0 || format.height == 0) {
    throw Error(tiff.path, page + " has no pixels (" + std::to_string(format.width) + "x" +
                               std::to_string(format.height) + ")");
  }
  if (photometric == PHOTOMETRIC_PALETTE) {
    throw Error(tiff.path, page + " is a palette colour image: convert to grayscale first");
  }
  if (samples_per_pixel != 1 ||
      (photometric != PHOTOMETRIC_MINISBLACK && photometric != PHOTOMETRIC_MINISWHITE)) {
    throw Error(tiff.path, page + " is a colour or multi-sample image (" +
                               std::to_string(samples_per_pixel) +
                               " samples per pixel, photometric " + std::to_string(photometric) +
                               "): convert to grayscale first");
  }
  if (photometric == PHOTOMETRIC_MINISWHITE) {
    throw Error(tiff.path, page +
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
    throw Error(tiff.path, page + " has " + std::to_string(bits) + "-bit " + kind +
                               " samples: mvox reads 8-bit unsigned, 16-bit unsigned or signed, "
                               "and 32-bit float");
  }
  if (!TIFFIsCODECConfigured(compression)) {
    throw Error(tiff.path, page + " uses compression " + std::to_string(compression) +
                               ", which this libtiff cannot decode");
  }
  format.compression = compression;
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
PageBuffers check_page_data(TiffStackSource::Tiff& tiff, std::uint64_t page_index,
                            std::uint64_t file_bytes, const PageFormat& format) {
  TIFF* t = tiff.handle;
  const std::string page = page_subject(page_index);
  const bool tiled = TIFFIsTiled(t) != 0;
  const std::string samples_text = " " + sample_text(format.type) + " samples";
  const std::uint64_t bytes_per_sample = sample_bytes(format.type);
  const std::uint64_t row_bytes = std::uint64_t{format.width} * bytes_per_sample;
  const CodecBound codec = codec_bound(format.compression);
  PageBuffers buffers;

  std::uint32_t tile_width = 0, tile_height = 0, rows_per_strip = format.height;
  if (tiled) {
    TIFFGetField(t, TIFFTAG_TILEWIDTH, &tile_width);
    TIFFGetField(t, TIFFTAG_TILELENGTH, &tile_height);
    const std::uint64_t tile_samples = std::uint64_t{tile_width} * tile_height;
    if (tile_samples == 0) {
      throw Error(tiff.path, page + ": invalid tile size " + std::to_string(tile_width) + "x" +
                                 std::to_string(tile_height));
    }
    const std::uint64_t image_samples =
        product(round_up_16(format.width), round_up_16(format.height));
    if (tile_samples > std::max(image_samples, kLargestFixedTileSamples)) {
      throw Error(tiff.path, page + ": its " + std::to_string(tile_width) + "x" +
                                 std::to_string(tile_height) + " tiles are far larger than the " +
                                 std::to_string(format.width) + "x" +
                                 std::to_string(format.height) +
                                 " image (a tile may hold the image rounded up to multiples of "
                                 "16, or 4096x4096 samples)");
    }
    buffers.tile = product(tile_samples, bytes_per_sample);
  } else {
    TIFFGetFieldDefaulted(t, TIFFTAG_ROWSPERSTRIP, &rows_per_strip);
    if (rows_per_strip == 0 || rows_per_strip > format.height) rows_per_strip = format.height;
  }

  const std::uint32_t count = tiled ? TIFFNumberOfTiles(t) : TIFFNumberOfStrips(t);
  std::uint64_t stored_total = 0, decoded_total = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string chunk = (tiled ? "tile " : "strip ") + std::to_string(i);
    int error = 0;
    const std::uint64_t offset = TIFFGetStrileOffsetWithErr(t, i, &error);
    const std::uint64_t bytes = error ? 0 : TIFFGetStrileByteCountWithErr(t, i, &error);
    if (error || bytes == 0) {
      throw Error(tiff.path, page + ": " + chunk + " has no data" + tiff.take_error());
    }
    if (offset > file_bytes || file_bytes - offset < bytes) {
      throw Error(tiff.path, page + ": " + chunk + " ends at byte " +
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
      throw Error(tiff.path, page + ": " + chunk + " declares " + std::to_string(decoded) +
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
    throw Error(tiff.path, page + " declares " + std::to_string(decoded_total) + " bytes (" +
                               std::to_string(format.width) + "x" + std::to_string(format.height) +
                               samples_text + ") in " + std::to_string(count) +
                               (tiled ? " tiles" : " strips") + stored_text(codec, stored_total));
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
void read_imagej_spacing(TIFF* t, VolumeInfo& info) {
  const char* description = nullptr;
  if (!TIFFGetField(t, TIFFTAG_IMAGEDESCRIPTION, &description) || !description) return;
  const std::string_view text(description);
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
  float resolution = 0;
  if (TIFFGetField(t, TIFFTAG_XRESOLUTION, &resolution) && resolution > 0 &&
      std::isfinite(1.0 / resolution)) {
    info.spacing[0] = 1.0 / resolution;
  }
  if (TIFFGetField(t, TIFFTAG_YRESOLUTION, &resolution) && resolution > 0 &&
      std::isfinite(1.0 / resolution)) {
    info.spacing[1] = 1.0 / resolution;
  }
}

}  // namespace

TiffStackSource::Tiff::Tiff(const std::string& file_path) : path(file_path) {
  std::error_code ignored;
  if (!std::filesystem::exists(path, ignored)) throw Error(path, "no such file");
  TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
  if (!options) throw Error(path, "out of memory opening the TIFF file");
  TIFFOpenOptionsSetErrorHandlerExtR(options, keep_first_error, this);
  TIFFOpenOptionsSetWarningHandlerExtR(options, drop_warning, this);
  // "m": read with read(2), not a memory map, so that streaming a large file does not grow the
  // process's resident memory with pages already used.
  handle = TIFFOpenExt(path.c_str(), "rm", options);
  TIFFOpenOptionsFree(options);
  if (!handle) {
    throw Error(
        path, "cannot read as TIFF (unreadable, corrupt, truncated or not a TIFF)" + take_error());
  }
}

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
  Tiff tiff(files_[file_index]);
  const std::uint64_t bytes = file_size(tiff.path);
  std::uint64_t page = 0;
  for (;;) {
    const PageFormat format = page_format(tiff, page);
    if (file_index == 0 && page == 0) {
      info_.width = format.width;
      info_.height = format.height;
      info_.type = format.type;
      read_imagej_spacing(tiff.handle, info_);
    } else {
      const PageFormat first{info_.width, info_.height, info_.type};
      if (!same_format(format, first)) {
        const std::string like = file_index == 0 ? "page 1" : "page 1 of " + files_[0];
        throw Error(tiff.path, page_subject(page) + " is " + std::to_string(format.width) + "x" +
                                   std::to_string(format.height) + " " + sample_text(format.type) +
                                   ", expected " + std::to_string(first.width) + "x" +
                                   std::to_string(first.height) + " " + sample_text(first.type) +
                                   " like " + like);
      }
    }
    const PageBuffers buffers = check_page_data(tiff, page, bytes, format);
    largest_tile_ = std::max(largest_tile_, buffers.tile);
    if (is_deflate(format.compression)) {
      largest_deflate_chunk_ = std::max(largest_deflate_chunk_, buffers.largest_chunk);
    } else if (format.compression != COMPRESSION_NONE) {
      largest_libtiff_chunk_ = std::max(largest_libtiff_chunk_, buffers.largest_chunk);
    }
    ++page;
    tiff.take_error();
    if (!TIFFReadDirectory(tiff.handle)) {
      // 0 both at the last page and on a broken directory; only the latter reports an error.
      if (!tiff.error.empty()) {
        throw Error(tiff.path, "cannot read the directory of page " + std::to_string(page + 1) +
                                   tiff.take_error());
      }
      break;
    }
  }
  pages_per_file_.push_back(page);
  *pages += page;
}

bool TiffStackSource::read_chunk(std::uint32_t index, bool deflate, unsigned char* out,
                                 std::size_t out_bytes, std::size_t row_samples) {
  TIFF* t = open_->handle;
  const bool tiled = TIFFIsTiled(t) != 0;
  if (!deflate) {
    const tmsize_t got =
        tiled ? TIFFReadEncodedTile(t, index, out, static_cast<tmsize_t>(out_bytes))
              : TIFFReadEncodedStrip(t, index, out, static_cast<tmsize_t>(out_bytes));
    return got == static_cast<tmsize_t>(out_bytes);
  }
  // libtiff's deflate decoder stops once it has the samples, often before the zlib checksum:
  // the stored bytes are read here and inflated whole, checksum included (zlib_stream_check.h).
  const std::string chunk =
      page_subject(page_in_file_) + ": " + (tiled ? "tile " : "strip ") + std::to_string(index);
  int error = 0;
  const std::uint64_t stored = TIFFGetStrileByteCountWithErr(t, index, &error);
  if (error) return false;
  // The constructor saw every strip and tile; the file may have changed since.
  if (stored > largest_deflate_chunk_) {
    throw Error(open_->path, chunk + " changed since the stack was opened");
  }
  grow_buffer(raw_, stored, open_->path, "the stored data of " + chunk);
  const tmsize_t got = tiled
                           ? TIFFReadRawTile(t, index, raw_.data(), static_cast<tmsize_t>(stored))
                           : TIFFReadRawStrip(t, index, raw_.data(), static_cast<tmsize_t>(stored));
  if (got != static_cast<tmsize_t>(stored)) {
    throw Error(open_->path, chunk + ": cannot read its " + std::to_string(stored) + " bytes" +
                                 open_->take_error());
  }
  // Bits stored in reverse order (FillOrder 2) are put right before inflating, as libtiff
  // does.
  std::uint16_t fill_order = FILLORDER_MSB2LSB;
  TIFFGetFieldDefaulted(t, TIFFTAG_FILLORDER, &fill_order);
  const bool reversed = fill_order == FILLORDER_LSB2MSB;
  if (reversed) TIFFReverseBits(raw_.data(), static_cast<tmsize_t>(stored));
  if (!deflate_check_) deflate_check_ = std::make_unique<ZlibStreamCheck>();
  ZlibStreamCheck::Result inflated;
  try {
    inflated =
        deflate_check_->inflate(raw_.data(), static_cast<std::size_t>(stored), out, out_bytes);
  } catch (const std::bad_alloc&) {
    throw Error(open_->path, "out of memory: cannot allocate zlib's state (about " +
                                 std::to_string(ZlibStreamCheck::kWorkingBytes) + " bytes)");
  }
  if (!inflated.problem.empty()) {
    throw Error(open_->path, chunk + ": corrupt deflate data (zlib: " + inflated.problem + ")");
  }
  if (inflated.total < out_bytes) {
    throw Error(open_->path, chunk + ": its deflate data decode to " +
                                 std::to_string(inflated.total) + " bytes, fewer than the " +
                                 std::to_string(out_bytes) + " it holds");
  }
  // What libtiff does after inflating: byte order and predictor.
  const std::size_t bytes_per_sample = sample_bytes(info_.type);
  std::uint16_t predictor = PREDICTOR_NONE;
  TIFFGetFieldDefaulted(t, TIFFTAG_PREDICTOR, &predictor);
  if (finish_tiff_samples(out, out_bytes / (row_samples * bytes_per_sample), row_samples,
                          bytes_per_sample, TIFFIsByteSwapped(t) != 0, predictor)) {
    return true;
  }
  // The floating-point predictor: libtiff decodes the checked bytes once more, from this buffer
  // (with their bits back in stored order, which it reverses itself).
  if (reversed) TIFFReverseBits(raw_.data(), static_cast<tmsize_t>(stored));
  return TIFFReadFromUserBuffer(t, index, raw_.data(), static_cast<tmsize_t>(stored), out,
                                static_cast<tmsize_t>(out_bytes)) != 0;
}

void TiffStackSource::read_page(ReadBuffer& buffer, std::uint16_t compression) {
  TIFF* t = open_->handle;
  const std::string page = page_subject(page_in_file_);
  const bool deflate = is_deflate(compression);
  // When libtiff decodes deflate itself (the floating-point predictor, read_chunk), it must not
  // use libdeflate: libtiff takes libdeflate's "insufficient space" as success, for writers
  // that store more rows than a strip holds, but libdeflate leaves the end of the output
  // unwritten then (zeros where samples belong). zlib fills it exactly.
  if (deflate && !TIFFSetField(t, TIFFTAG_DEFLATE_SUBCODEC, DEFLATE_SUBCODEC_ZLIB)) {
    throw Error(open_->path,
                page + ": libtiff cannot decode deflate with zlib" + open_->take_error());
  }
  const std::size_t bytes_per_sample = sample_bytes(info_.type);
  const std::size_t row_bytes = static_cast<std::size_t>(info_.width) * bytes_per_sample;
  open_->take_error();

  if (!TIFFIsTiled(t)) {
    std::uint32_t rows_per_strip = 0;
    TIFFGetFieldDefaulted(t, TIFFTAG_ROWSPERSTRIP, &rows_per_strip);
    if (rows_per_strip == 0 || rows_per_strip > info_.height) rows_per_strip = info_.height;
    for (std::uint32_t row = 0; row < info_.height; row += rows_per_strip) {
      const std::uint32_t rows = std::min(rows_per_strip, info_.height - row);
      if (!read_chunk(TIFFComputeStrip(t, row, 0), deflate, buffer.data() + row * row_bytes,
                      rows * row_bytes, info_.width)) {
        throw Error(open_->path, page + ": cannot decode the strip at row " + std::to_string(row) +
                                     open_->take_error());
      }
    }
    return;
  }

  std::uint32_t tile_width = 0, tile_height = 0;
  TIFFGetField(t, TIFFTAG_TILEWIDTH, &tile_width);
  TIFFGetField(t, TIFFTAG_TILELENGTH, &tile_height);
  const std::uint64_t tile_bytes = product(product(tile_width, tile_height), bytes_per_sample);
  // The constructor checked the tile size; the file may have changed since.
  if (tile_width == 0 || tile_height == 0 || TIFFTileSize64(t) < tile_bytes ||
      tile_bytes > largest_tile_) {
    throw Error(open_->path, page + ": invalid tile size " + std::to_string(tile_width) + "x" +
                                 std::to_string(tile_height));
  }
  grow_buffer(tile_, tile_bytes, open_->path,
              "a " + std::to_string(tile_width) + "x" + std::to_string(tile_height) + " tile");
  for (std::uint32_t y = 0; y < info_.height; y += tile_height) {
    for (std::uint32_t x = 0; x < info_.width; x += tile_width) {
      if (!read_chunk(TIFFComputeTile(t, x, y, 0, 0), deflate, tile_.data(),
                      static_cast<std::size_t>(tile_bytes), tile_width)) {
        throw Error(open_->path, page + ": cannot decode the tile at x " + std::to_string(x) +
                                     ", y " + std::to_string(y) + open_->take_error());
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
    open_ = std::make_unique<Tiff>(files_[file_index_]);
    page_in_file_ = 0;
  } else {
    open_->take_error();
    if (!TIFFReadDirectory(open_->handle)) {
      throw Error(open_->path, "cannot read the directory of page " +
                                   std::to_string(page_in_file_ + 1) + open_->take_error());
    }
  }
  // Checked again while streaming: the file may have changed since the constructor looked.
  const PageFormat format = page_format(*open_, page_in_file_);
  if (!same_format(format, PageFormat{info_.width, info_.height, info_.type})) {
    throw Error(open_->path, page_subject(page_in_file_) + " changed since the stack was opened");
  }
  grow_buffer(buffer_, slice_bytes(info_), open_->path,
              "the " + std::to_string(info_.width) + "x" + std::to_string(info_.height) + " slice");
  read_page(buffer_, format.compression);

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
  TiffStackSource::Tiff tiff(path);
  std::uint64_t pages = 1;
  while (TIFFReadDirectory(tiff.handle)) ++pages;
  if (!tiff.error.empty()) {
    throw Error(
        path, "cannot read the directory of page " + std::to_string(pages + 1) + tiff.take_error());
  }
  return pages;
}

}  // namespace mvox
