#include "tiff_stack_source.h"

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
#include <utility>

#include "error.h"
#include "header_text.h"

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
  return format;
}

// Refuses a page whose strips or tiles do not lie inside the file: the file was cut short.
void check_page_data(TiffStackSource::Tiff& tiff, std::uint64_t page_index,
                     std::uint64_t file_bytes) {
  TIFF* t = tiff.handle;
  const bool tiled = TIFFIsTiled(t) != 0;
  const std::uint32_t count = tiled ? TIFFNumberOfTiles(t) : TIFFNumberOfStrips(t);
  for (std::uint32_t i = 0; i < count; ++i) {
    int error = 0;
    const std::uint64_t offset = TIFFGetStrileOffsetWithErr(t, i, &error);
    const std::uint64_t bytes = error ? 0 : TIFFGetStrileByteCountWithErr(t, i, &error);
    if (error || bytes == 0) {
      throw Error(tiff.path, page_subject(page_index) + ": " + (tiled ? "tile " : "strip ") +
                                 std::to_string(i) + " has no data" + tiff.take_error());
    }
    if (offset > file_bytes || file_bytes - offset < bytes) {
      throw Error(tiff.path, page_subject(page_index) + ": " + (tiled ? "tile " : "strip ") +
                                 std::to_string(i) + " ends at byte " +
                                 std::to_string(offset + bytes) + ", but the file is " +
                                 std::to_string(file_bytes) + " bytes (truncated)");
    }
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
  buffer_.resize(static_cast<std::size_t>(info_.width) * info_.height * sample_bytes(info_.type));
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
    check_page_data(tiff, page, bytes);
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

void TiffStackSource::read_page(std::vector<unsigned char>& buffer) {
  TIFF* t = open_->handle;
  const std::string page = page_subject(page_in_file_);
  const std::size_t bytes_per_sample = sample_bytes(info_.type);
  const std::size_t row_bytes = static_cast<std::size_t>(info_.width) * bytes_per_sample;
  open_->take_error();

  if (!TIFFIsTiled(t)) {
    std::uint32_t rows_per_strip = 0;
    TIFFGetFieldDefaulted(t, TIFFTAG_ROWSPERSTRIP, &rows_per_strip);
    if (rows_per_strip == 0 || rows_per_strip > info_.height) rows_per_strip = info_.height;
    for (std::uint32_t row = 0; row < info_.height; row += rows_per_strip) {
      const std::uint32_t rows = std::min(rows_per_strip, info_.height - row);
      const auto wanted = static_cast<tmsize_t>(rows * row_bytes);
      const tmsize_t got = TIFFReadEncodedStrip(t, TIFFComputeStrip(t, row, 0),
                                                buffer.data() + row * row_bytes, wanted);
      if (got != wanted) {
        throw Error(open_->path, page + ": cannot decode the strip at row " + std::to_string(row) +
                                     open_->take_error());
      }
    }
    return;
  }

  std::uint32_t tile_width = 0, tile_height = 0;
  TIFFGetField(t, TIFFTAG_TILEWIDTH, &tile_width);
  TIFFGetField(t, TIFFTAG_TILELENGTH, &tile_height);
  const std::uint64_t tile_bytes = std::uint64_t{tile_width} * tile_height * bytes_per_sample;
  if (tile_width == 0 || tile_height == 0 || TIFFTileSize64(t) < tile_bytes) {
    throw Error(open_->path, page + ": invalid tile size " + std::to_string(tile_width) + "x" +
                                 std::to_string(tile_height));
  }
  tile_.resize(static_cast<std::size_t>(tile_bytes));
  for (std::uint32_t y = 0; y < info_.height; y += tile_height) {
    for (std::uint32_t x = 0; x < info_.width; x += tile_width) {
      const tmsize_t got = TIFFReadEncodedTile(t, TIFFComputeTile(t, x, y, 0, 0), tile_.data(),
                                               static_cast<tmsize_t>(tile_.size()));
      if (got != static_cast<tmsize_t>(tile_.size())) {
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
  read_page(buffer_);

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
