#include "read/tiff/tiff_stack_source.h"

#include <tiff.h>  // TIFF's tag values, by name; libtiff itself is the TIFF module's (tiff_file.h)

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>
#include <utility>

#include "error.h"
#include "read/compression_bounds.h"
#include "read/file_names.h"
#include "read/header_text.h"
#include "read/tiff/tiff_directory.h"
#include "read/tiff/tiff_file.h"
#include "read/tiff/tiff_predictor.h"

namespace mvox {

namespace {

// What a page holds, as far as the stack cares.
struct PageFormat {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  SampleType type = SampleType::u8;
};

bool is_deflate(std::uint16_t compression) {
  return compression == COMPRESSION_ADOBE_DEFLATE || compression == COMPRESSION_DEFLATE;
}

// Uncompressed data are read by mvox, and deflate data inflated and finished by it unless
// they use a predictor tiff_predictor.h does not undo; only libtiff decodes the others.
bool decoded_by_libtiff(const TiffDirectory& page) {
  if (page.compression == COMPRESSION_NONE) return false;
  return !is_deflate(page.compression) ||
         (page.predictor != PREDICTOR_NONE && page.predictor != PREDICTOR_HORIZONTAL);
}

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

// The codecs libtiff decodes for samples of 1 to 4 bits only, never for the 8 to 32 bits mvox
// reads; such a page is refused by its directory, before its slice is allocated. nullptr for
// other codecs.
const char* narrow_sample_codec(std::uint16_t compression) {
  switch (compression) {
    case COMPRESSION_CCITTRLE:
    case COMPRESSION_CCITTFAX3:
    case COMPRESSION_CCITTFAX4:
    case COMPRESSION_CCITTRLEW: return "CCITT, bilevel";
    case COMPRESSION_JBIG: return "JBIG, bilevel";
    case COMPRESSION_NEXT: return "NeXT, 2-bit";
    case COMPRESSION_THUNDERSCAN: return "ThunderScan, 4-bit";
    default: return nullptr;
  }
}

// Checks a page's format. Refusals name the page (1-based).
PageFormat page_format(const TiffDirectory& tags, const std::string& path,
                       std::uint64_t page_index) {
  const std::string page = page_subject(page_index);
  PageFormat format;
  format.width = tags.width;
  format.height = tags.height;
  const std::uint16_t samples_per_pixel = tags.samples_per_pixel;
  const std::uint16_t bits = tags.bits_per_sample;
  const std::uint16_t sample_format = tags.sample_format;
  const std::uint16_t photometric = tags.photometric;
  const std::uint16_t compression = tags.compression;

  if (format.width == 0 || format.height == 0) {
    throw Error(path, page + " has no pixels (" + std::to_string(format.width) + "x" +
                          std::to_string(format.height) + ")");
  }
  if (photometric == PHOTOMETRIC_PALETTE) {
    throw Error(path, page + " is a palette colour image: convert to grayscale first");
  }
  if (samples_per_pixel != 1 ||
      (photometric != PHOTOMETRIC_MINISBLACK && photometric != PHOTOMETRIC_MINISWHITE)) {
    throw Error(path, page + " is a colour or multi-sample image (" +
                          std::to_string(samples_per_pixel) + " samples per pixel, photometric " +
                          std::to_string(photometric) + "): convert to grayscale first");
  }
  if (photometric == PHOTOMETRIC_MINISWHITE) {
    throw Error(path, page +
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
    throw Error(path, page + " has " + std::to_string(bits) + "-bit " + kind +
                          " samples: mvox reads 8-bit unsigned, 16-bit unsigned or signed, "
                          "and 32-bit float");
  }
  if (const char* codec = narrow_sample_codec(compression)) {
    throw Error(path, page + " uses compression " + std::to_string(compression) + " (" + codec +
                          "), which holds samples of 1 to 4 bits, not the " + std::to_string(bits) +
                          " bits it declares");
  }
  if (decoded_by_libtiff(tags) && !tiff_codec_configured(compression, path)) {
    throw Error(path, page + " uses compression " + std::to_string(compression) +
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
PageBuffers check_page_data(const TiffDirectory& tags, const std::string& path,
                            std::uint64_t page_index, std::uint64_t file_bytes,
                            const PageFormat& format) {
  const std::string page = page_subject(page_index);
  const bool tiled = tags.tiled;
  const std::string samples_text = " " + sample_text(format.type) + " samples";
  const std::uint64_t bytes_per_sample = sample_bytes(format.type);
  const std::uint64_t row_bytes = std::uint64_t{format.width} * bytes_per_sample;
  const CodecBound codec = codec_bound(tags.compression);
  PageBuffers buffers;

  std::uint32_t tile_width = 0, tile_height = 0, rows_per_strip = format.height;
  if (tiled) {
    tile_width = tags.tile_width;
    tile_height = tags.tile_height;
    const std::uint64_t tile_samples = std::uint64_t{tile_width} * tile_height;
    if (tile_samples == 0) {
      throw Error(path, page + ": invalid tile size " + std::to_string(tile_width) + "x" +
                            std::to_string(tile_height));
    }
    const std::uint64_t image_samples =
        product(round_up_16(format.width), round_up_16(format.height));
    if (tile_samples > std::max(image_samples, kLargestFixedTileSamples)) {
      throw Error(path, page + ": its " + std::to_string(tile_width) + "x" +
                            std::to_string(tile_height) + " tiles are far larger than the " +
                            std::to_string(format.width) + "x" + std::to_string(format.height) +
                            " image (a tile may hold the image rounded up to multiples of "
                            "16, or 4096x4096 samples)");
    }
    buffers.tile = product(tile_samples, bytes_per_sample);
  } else {
    rows_per_strip = tags.strip_rows();
  }

  const std::size_t count = tags.chunk_offsets.size();
  std::uint64_t stored_total = 0, decoded_total = 0;
  for (std::size_t i = 0; i < count; ++i) {
    // Named only for a refusal: a page may have thousands of strips.
    const auto chunk = [&] { return (tiled ? "tile " : "strip ") + std::to_string(i); };
    const std::uint64_t offset = tags.chunk_offsets[i], bytes = tags.chunk_bytes[i];
    if (bytes == 0) throw Error(path, page + ": " + chunk() + " has no data");
    if (offset > file_bytes || file_bytes - offset < bytes) {
      throw Error(path, page + ": " + chunk() + " ends at byte " + std::to_string(offset + bytes) +
                            ", but the file is " + std::to_string(file_bytes) +
                            " bytes (truncated)");
    }
    // A strip holds rows_per_strip rows, the last one what is left; a tile is whole even
    // where it reaches past the image.
    std::uint64_t decoded = buffers.tile, rows = 0;
    if (!tiled) {
      const std::uint64_t first_row = std::uint64_t{i} * rows_per_strip;
      rows = first_row >= format.height
                 ? 0
                 : std::min<std::uint64_t>(rows_per_strip, format.height - first_row);
      decoded = product(rows, row_bytes);
    }
    if (!could_hold(codec, bytes, decoded)) {
      const std::string declared =
          tiled ? std::to_string(tile_width) + "x" + std::to_string(tile_height)
                : std::to_string(rows) + " rows of " + std::to_string(format.width);
      throw Error(path, page + ": " + chunk() + " declares " + std::to_string(decoded) +
                            " bytes (" + declared + samples_text + ")" + stored_text(codec, bytes));
    }
    stored_total = sum(stored_total, bytes);
    decoded_total = sum(decoded_total, decoded);
    buffers.largest_chunk = std::max(buffers.largest_chunk, bytes);
  }
  // Many small strips or tiles, each within its codec's allowance for a stream's overhead,
  // must not add up to a page that the file cannot hold either.
  if (!could_hold(codec, stored_total, decoded_total)) {
    throw Error(path, page + " declares " + std::to_string(decoded_total) + " bytes (" +
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

bool same_format(const PageFormat& a, const PageFormat& b) {
  return a.width == b.width && a.height == b.height && a.type == b.type;
}

// ImageJ writes stacks with "ImageJ=1.x\nimages=N\nslices=N\nunit=mm\nspacing=2.5\n..." in the
// ImageDescription and the pixel size as XResolution/YResolution (pixels per unit).
void read_imagej_spacing(const TiffDirectory& tags, VolumeInfo& info) {
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

// Moves `libtiff`, at page *at (0-based), on to page `page_index`, whose directory mvox read
// at byte `directory` as `ours`, and checks that libtiff reads it the same: libtiff decodes by
// its own reading. The next page is libtiff's next directory; a page further on (a slab
// worker's first) is read at its offset, not after every directory before it.
void move_libtiff_to(TiffFile& libtiff, std::uint64_t* at, std::uint64_t page_index,
                     std::uint64_t directory, const TiffDirectory& ours, bool byte_swapped) {
  const std::string page = page_subject(page_index);
  if (*at != page_index) {
    libtiff.take_error();
    const bool read =
        page_index == *at + 1 ? libtiff.read_directory() : libtiff.read_directory_at(directory);
    if (!read) {
      throw Error(libtiff.path(),
                  "libtiff cannot read the directory of " + page + libtiff.take_error());
    }
    *at = page_index;
  }
  const mvox_tiff_page theirs = libtiff.tags();
  bool same = theirs.width == ours.width && theirs.height == ours.height &&
              theirs.samples_per_pixel == ours.samples_per_pixel &&
              theirs.bits_per_sample == ours.bits_per_sample &&
              theirs.sample_format == ours.sample_format &&
              theirs.compression == ours.compression && theirs.fill_order == ours.fill_order &&
              theirs.predictor == ours.predictor && (theirs.byte_swapped != 0) == byte_swapped &&
              (theirs.tiled != 0) == ours.tiled && theirs.chunks == ours.chunk_offsets.size();
  if (same && ours.tiled) {
    same = theirs.tile_width == ours.tile_width && theirs.tile_height == ours.tile_height;
  } else if (same) {
    const std::uint32_t rows = theirs.rows_per_strip;
    same = (rows == 0 || rows > theirs.height ? theirs.height : rows) == ours.strip_rows();
  }
  for (std::uint32_t i = 0; same && i < theirs.chunks; ++i) {
    std::uint64_t offset = 0, bytes = 0;
    same = libtiff.chunk_location(i, &offset, &bytes) && offset == ours.chunk_offsets[i] &&
           bytes == ours.chunk_bytes[i];
  }
  if (!same) {
    throw Error(libtiff.path(),
                page + ": libtiff reads its directory otherwise than mvox" + libtiff.take_error());
  }
}

}  // namespace

TiffStackSource::TiffStackSource(std::vector<std::string> files) {
  files_->paths = std::move(files);
  if (files_->paths.empty()) throw Error("INPUT", "no TIFF files");
  std::uint64_t pages = 0;
  for (std::size_t i = 0; i < files_->paths.size(); ++i) check_file(i, &pages);
  if (pages > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("INPUT", "more than 2^32-1 TIFF pages");
  }
  info_.depth = static_cast<std::uint32_t>(pages);
  end_index_ = info_.depth;
  // No buffer yet: they come with the first slice (next_slice), after every directory has
  // been checked, and so after every refusal that needs no decoding.
}

TiffStackSource::TiffStackSource(const TiffStackSource& whole, std::uint32_t first,
                                 std::uint32_t end)
    : files_(whole.files_),
      info_(whole.info_),
      largest_tile_(whole.largest_tile_),
      largest_deflate_chunk_(whole.largest_deflate_chunk_),
      largest_libtiff_chunk_(whole.largest_libtiff_chunk_),
      largest_chunk_count_(whole.largest_chunk_count_),
      compressed_pages_(whole.compressed_pages_),
      next_index_(first),
      end_index_(std::min(end, whole.info_.depth)) {
  // The file holding slice `first`, and its page there; next_slice walks up to it.
  std::uint64_t page = first;
  const std::vector<std::uint64_t>& pages = files_->pages;
  while (file_index_ < pages.size() && page >= pages[file_index_]) {
    page -= pages[file_index_];
    ++file_index_;
  }
  page_in_file_ = page;
}

std::unique_ptr<SliceSource> TiffStackSource::open_range(std::uint32_t first,
                                                         std::uint32_t end) const {
  return std::unique_ptr<SliceSource>(new TiffStackSource(*this, first, end));
}

std::uint64_t TiffStackSource::working_bytes() const {
  const std::uint64_t slice = slice_bytes(info_);
  // libtiff reads a stored strip or tile into a buffer rounded up to 1 KiB (TIFFReadBufferSetup);
  // uncompressed ones go straight into mvox's buffers.
  const std::uint64_t libtiff_raw = (largest_libtiff_chunk_ + 1023) / 1024 * 1024;
  const std::uint64_t deflate =
      largest_deflate_chunk_ == 0 ? 0 : largest_deflate_chunk_ + ZlibStreamCheck::kWorkingBytes;
  // The current page's strip or tile offsets and byte counts.
  const std::uint64_t locations = product(largest_chunk_count_, 2 * sizeof(std::uint64_t));
  return sum(sum(sum(slice, largest_tile_), sum(libtiff_raw, deflate)), locations);
}

TiffStackSource::~TiffStackSource() = default;

void TiffStackSource::check_file(std::size_t file_index, std::uint64_t* pages) {
  TiffDirectoryReader reader(files_->paths[file_index]);
  const std::string& path = reader.path();
  TiffDirectory tags;
  std::unique_ptr<TiffFile> libtiff;  // opened at the first page that libtiff decodes
  std::uint64_t libtiff_page = 0;
  std::uint64_t page = 0;
  std::vector<std::uint64_t> marks;
  for (;;) {
    if (page % kPagesPerMark == 0) marks.push_back(reader.next_directory());
    if (!reader.next(&tags)) break;
    const PageFormat format = page_format(tags, path, page);
    if (file_index == 0 && page == 0) {
      info_.width = format.width;
      info_.height = format.height;
      info_.type = format.type;
      read_imagej_spacing(tags, info_);
    } else {
      const PageFormat first{info_.width, info_.height, info_.type};
      if (!same_format(format, first)) {
        const std::string like = file_index == 0 ? "page 1" : "page 1 of " + files_->paths[0];
        throw Error(path, page_subject(page) + " is " + std::to_string(format.width) + "x" +
                              std::to_string(format.height) + " " + sample_text(format.type) +
                              ", expected " + std::to_string(first.width) + "x" +
                              std::to_string(first.height) + " " + sample_text(first.type) +
                              " like " + like);
      }
    }
    const PageBuffers buffers = check_page_data(tags, path, page, reader.file_bytes(), format);
    // Pages libtiff decodes are read by libtiff too, now, so that a directory it refuses or
    // reads otherwise is refused before any slice is read.
    if (decoded_by_libtiff(tags)) {
      if (!libtiff) libtiff = std::make_unique<TiffFile>(path);
      move_libtiff_to(*libtiff, &libtiff_page, page, reader.directory(), tags,
                      reader.byte_swapped());
    }
    largest_tile_ = std::max(largest_tile_, buffers.tile);
    largest_chunk_count_ = std::max<std::uint64_t>(largest_chunk_count_, tags.chunk_offsets.size());
    if (tags.compression != COMPRESSION_NONE) compressed_pages_ = true;
    if (is_deflate(tags.compression)) {
      largest_deflate_chunk_ = std::max(largest_deflate_chunk_, buffers.largest_chunk);
    } else if (tags.compression != COMPRESSION_NONE) {
      largest_libtiff_chunk_ = std::max(largest_libtiff_chunk_, buffers.largest_chunk);
    }
    ++page;
  }
  files_->pages.push_back(page);
  files_->directory_marks.push_back(std::move(marks));
  *pages += page;
}

void TiffStackSource::position_libtiff() {
  const std::string& path = open_->path();
  if (!libtiff_) {
    libtiff_ = std::make_unique<TiffFile>(path);
    libtiff_page_ = 0;
  }
  move_libtiff_to(*libtiff_, &libtiff_page_, page_in_file_, open_->directory(), page_,
                  open_->byte_swapped());
  // When libtiff decodes deflate (the floating-point predictor), it must not use libdeflate,
  // which can leave the end of a strip unwritten (tiff_codecs_api.h).
  if (is_deflate(page_.compression) && !libtiff_->inflate_with_zlib()) {
    throw Error(path, page_subject(page_in_file_) + ": libtiff cannot decode deflate with zlib" +
                          libtiff_->take_error());
  }
}

void TiffStackSource::read_chunk(std::uint32_t index, unsigned char* out, std::size_t out_bytes,
                                 std::size_t row_samples) {
  const std::string& path = open_->path();
  // Named only for a message: this runs for every strip or tile of every page.
  const auto chunk = [&] {
    return page_subject(page_in_file_) + ": " + (page_.tiled ? "tile " : "strip ") +
           std::to_string(index);
  };
  const std::uint64_t offset = page_.chunk_offsets[index], stored = page_.chunk_bytes[index];
  const bool deflate = is_deflate(page_.compression);
  if (!deflate && page_.compression != COMPRESSION_NONE) {
    if (!libtiff_->read_chunk(index, out, out_bytes)) {
      throw Error(path, chunk() + ": libtiff cannot decode it" + libtiff_->take_error());
    }
    return;
  }
  // The constructor saw every strip and tile; the file may have changed since.
  if (deflate ? stored > largest_deflate_chunk_ : stored < out_bytes) {
    throw Error(path, chunk() + " changed since the stack was opened");
  }
  const bool reversed = page_.fill_order == FILLORDER_LSB2MSB;
  const std::size_t bytes_per_sample = sample_bytes(info_.type);
  const std::size_t rows = out_bytes / (row_samples * bytes_per_sample);
  if (!deflate) {
    // Uncompressed: the stored bytes are the samples, bits and bytes in the file's order.
    open_->read_at(offset, out, out_bytes);
    if (reversed) reverse_bit_order(out, out_bytes);
    finish_tiff_samples(out, rows, row_samples, bytes_per_sample, open_->byte_swapped(),
                        PREDICTOR_NONE);
    return;
  }
  // libtiff's deflate decoder stops once it has the samples, often before the zlib checksum:
  // the stored bytes are inflated whole here, checksum included (zlib_stream_check.h).
  if (raw_.size() < stored) grow_buffer(raw_, stored, path, "the stored data of " + chunk());
  open_->read_at(offset, raw_.data(), static_cast<std::size_t>(stored));
  // Bits stored in reverse order (FillOrder 2) are put right before inflating, as libtiff
  // does.
  if (reversed) reverse_bit_order(raw_.data(), static_cast<std::size_t>(stored));
  if (!deflate_check_) deflate_check_ = std::make_unique<ZlibStreamCheck>();
  ZlibStreamCheck::Result inflated;
  try {
    inflated =
        deflate_check_->inflate(raw_.data(), static_cast<std::size_t>(stored), out, out_bytes);
  } catch (const std::bad_alloc&) {
    throw Error(path, "out of memory: cannot allocate zlib's state (about " +
                          std::to_string(ZlibStreamCheck::kWorkingBytes) + " bytes)");
  }
  if (!inflated.problem.empty()) {
    throw Error(path, chunk() + ": corrupt deflate data (zlib: " + inflated.problem + ")");
  }
  if (inflated.total < out_bytes) {
    throw Error(path, chunk() + ": its deflate data decode to " + std::to_string(inflated.total) +
                          " bytes, fewer than the " + std::to_string(out_bytes) + " it holds");
  }
  // What libtiff does after inflating: byte order and predictor.
  if (finish_tiff_samples(out, rows, row_samples, bytes_per_sample, open_->byte_swapped(),
                          page_.predictor)) {
    return;
  }
  // The floating-point predictor: libtiff decodes the checked bytes once more, from this buffer
  // (with their bits back in stored order, which it reverses itself).
  if (reversed) reverse_bit_order(raw_.data(), static_cast<std::size_t>(stored));
  if (!libtiff_->decode_stored_chunk(index, raw_.data(), stored, out, out_bytes)) {
    throw Error(path, chunk() + ": libtiff cannot decode it" + libtiff_->take_error());
  }
}

void TiffStackSource::read_page(ReadBuffer& buffer) {
  const std::size_t bytes_per_sample = sample_bytes(info_.type);
  const std::size_t row_bytes = static_cast<std::size_t>(info_.width) * bytes_per_sample;

  if (!page_.tiled) {
    const std::uint32_t rows_per_strip = page_.strip_rows();
    // 64-bit counters: a strip's rows added to a row past 2^31 must not wrap round.
    for (std::uint64_t row = 0; row < info_.height; row += rows_per_strip) {
      const std::uint64_t rows = std::min<std::uint64_t>(rows_per_strip, info_.height - row);
      read_chunk(page_.chunk_at(0, static_cast<std::uint32_t>(row)),
                 buffer.data() + row * row_bytes, static_cast<std::size_t>(rows * row_bytes),
                 info_.width);
    }
    return;
  }

  const std::uint32_t tile_width = page_.tile_width, tile_height = page_.tile_height;
  const std::uint64_t tile_bytes = product(product(tile_width, tile_height), bytes_per_sample);
  // The constructor checked the tile size; the file may have changed since.
  if (tile_width == 0 || tile_height == 0 || tile_bytes > largest_tile_) {
    throw Error(open_->path(), page_subject(page_in_file_) + ": invalid tile size " +
                                   std::to_string(tile_width) + "x" + std::to_string(tile_height));
  }
  grow_buffer(tile_, tile_bytes, open_->path(),
              "a " + std::to_string(tile_width) + "x" + std::to_string(tile_height) + " tile");
  for (std::uint64_t y = 0; y < info_.height; y += tile_height) {
    for (std::uint64_t x = 0; x < info_.width; x += tile_width) {
      read_chunk(page_.chunk_at(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y)),
                 tile_.data(), static_cast<std::size_t>(tile_bytes), tile_width);
      // Tiles on the right and bottom edges reach past the image; only their inside is copied.
      const std::uint64_t rows = std::min<std::uint64_t>(tile_height, info_.height - y);
      const std::size_t copy_bytes = static_cast<std::size_t>(
          std::min<std::uint64_t>(tile_width, info_.width - x) * bytes_per_sample);
      for (std::uint64_t r = 0; r < rows; ++r) {
        std::memcpy(buffer.data() + (y + r) * row_bytes + x * bytes_per_sample,
                    tile_.data() + std::size_t{r} * tile_width * bytes_per_sample, copy_bytes);
      }
    }
  }
}

bool TiffStackSource::next_slice(SliceView* slice) {
  if (next_index_ >= end_index_) return false;
  if (open_ && page_in_file_ >= files_->pages[file_index_]) {
    open_.reset();
    libtiff_.reset();
    ++file_index_;
    page_in_file_ = 0;
  }
  const auto gone = [&](std::uint64_t page) {
    return Error(open_->path(), page_subject(page) + " is gone since the stack was opened");
  };
  if (!open_) {
    open_ = std::make_unique<TiffDirectoryReader>(files_->paths[file_index_]);
    // A range may start inside the file: from the mark before its first page, the directories
    // are walked up to it.
    const std::uint64_t mark = page_in_file_ / kPagesPerMark;
    open_->go_to_directory(files_->directory_marks[file_index_][mark], mark * kPagesPerMark);
    for (std::uint64_t page = mark * kPagesPerMark; page < page_in_file_; ++page) {
      if (!open_->next(&page_)) throw gone(page);
    }
  }
  if (!open_->next(&page_)) throw gone(page_in_file_);
  // Checked again while streaming: the file may have changed since the constructor looked.
  const PageFormat format = page_format(page_, open_->path(), page_in_file_);
  if (!same_format(format, PageFormat{info_.width, info_.height, info_.type}) ||
      page_.chunk_offsets.size() > largest_chunk_count_) {
    throw Error(open_->path(), page_subject(page_in_file_) + " changed since the stack was opened");
  }
  if (decoded_by_libtiff(page_)) position_libtiff();
  grow_buffer(buffer_, slice_bytes(info_), open_->path(),
              "the " + std::to_string(info_.width) + "x" + std::to_string(info_.height) + " slice");
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
  const std::string extension = lowercase_extension(path);
  return extension == ".tif" || extension == ".tiff";
}

std::uint64_t tiff_page_count(const std::string& path) {
  TiffDirectoryReader reader(path);
  TiffDirectory page;
  std::uint64_t pages = 0;
  while (reader.next(&page)) ++pages;
  return pages;
}

}  // namespace mvox
