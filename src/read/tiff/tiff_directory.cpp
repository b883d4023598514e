#include "read/tiff/tiff_directory.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>

#include "error.h"
#include "read/raw_file.h"

namespace mvox {

namespace {

// TIFF's tag numbers and field types (TIFF 6.0, section 2; BigTIFF adds types 16 to 18).
enum Tag : std::uint16_t {
  kImageWidth = 256,
  kImageLength = 257,
  kBitsPerSample = 258,
  kCompression = 259,
  kPhotometric = 262,
  kFillOrder = 266,
  kImageDescription = 270,
  kStripOffsets = 273,
  kSamplesPerPixel = 277,
  kRowsPerStrip = 278,
  kStripByteCounts = 279,
  kXResolution = 282,
  kYResolution = 283,
  kPredictor = 317,
  kTileWidth = 322,
  kTileLength = 323,
  kTileOffsets = 324,
  kTileByteCounts = 325,
  kSampleFormat = 339,
};

enum FieldType : std::uint16_t {
  kByte = 1,
  kAscii = 2,
  kShort = 3,
  kLong = 4,
  kRational = 5,
  kSignedByte = 6,
  kUndefined = 7,
  kSignedShort = 8,
  kSignedLong = 9,
  kSignedRational = 10,
  kFloat = 11,
  kDouble = 12,
  kIfd = 13,
  kLong8 = 16,
  kSignedLong8 = 17,
  kIfd8 = 18,
};

// Bytes of one value of `type`; 0 for a type TIFF does not define.
unsigned type_bytes(std::uint16_t type) {
  switch (type) {
    case kByte:
    case kAscii:
    case kSignedByte:
    case kUndefined: return 1;
    case kShort:
    case kSignedShort: return 2;
    case kLong:
    case kSignedLong:
    case kFloat:
    case kIfd: return 4;
    case kRational:
    case kSignedRational:
    case kDouble:
    case kLong8:
    case kSignedLong8:
    case kIfd8: return 8;
    default: return 0;
  }
}

bool is_signed(std::uint16_t type) {
  return type == kSignedByte || type == kSignedShort || type == kSignedLong || type == kSignedLong8;
}

bool is_integer(std::uint16_t type) {
  return type == kByte || type == kShort || type == kLong || type == kIfd || type == kLong8 ||
         type == kIfd8 || is_signed(type);
}

// libtiff's own sanity limit: a directory of more entries is taken for a wrong offset.
constexpr std::uint64_t kMostEntries = 4096;
// The first read of a directory (tiff_directory.cpp, read_directory).
constexpr std::uint64_t kFirstRead = 512;
// ImageJ's "spacing=" is in the first lines of its description; the rest is never looked at.
constexpr std::uint64_t kDescriptionBytes = 64 * 1024;

std::uint64_t saturating_product(std::uint64_t a, std::uint64_t b) {
  std::uint64_t result;
  return __builtin_mul_overflow(a, b, &result) ? std::numeric_limits<std::uint64_t>::max() : result;
}

std::uint64_t ceil_div(std::uint64_t a, std::uint64_t b) { return a / b + (a % b != 0); }

const char* tag_name(std::uint16_t tag) {
  switch (tag) {
    case kImageWidth: return "ImageWidth";
    case kImageLength: return "ImageLength";
    case kBitsPerSample: return "BitsPerSample";
    case kCompression: return "Compression";
    case kPhotometric: return "PhotometricInterpretation";
    case kFillOrder: return "FillOrder";
    case kImageDescription: return "ImageDescription";
    case kXResolution: return "XResolution";
    case kYResolution: return "YResolution";
    case kSamplesPerPixel: return "SamplesPerPixel";
    case kRowsPerStrip: return "RowsPerStrip";
    case kPredictor: return "Predictor";
    case kTileWidth: return "TileWidth";
    case kTileLength: return "TileLength";
    case kSampleFormat: return "SampleFormat";
    case kStripOffsets: return "StripOffsets";
    case kStripByteCounts: return "StripByteCounts";
    case kTileOffsets: return "TileOffsets";
    case kTileByteCounts: return "TileByteCounts";
    default: return "tag";  // never asked: only the tags above are read
  }
}

}  // namespace

// One directory entry: its tag, type, count, and its value field as stored (the values
// themselves when they fit in it, otherwise their offset).
struct TiffDirectoryReader::Entry {
  std::uint16_t tag = 0;
  std::uint16_t type = 0;
  std::uint64_t count = 0;
  unsigned char field[8] = {};
  unsigned field_bytes = 4;  // 8 in BigTIFF
  std::uint64_t offset = 0;  // of the values, when they do not fit in the field
  bool present = false;

  std::uint64_t value_bytes() const { return saturating_product(count, type_bytes(type)); }
  bool values_in_field() const { return value_bytes() <= field_bytes; }
};

std::uint32_t TiffDirectory::strip_rows() const {
  if (height == 0) return 0;
  return rows_per_strip == 0 || rows_per_strip > height ? height : rows_per_strip;
}

std::uint32_t TiffDirectory::chunk_at(std::uint32_t x, std::uint32_t y) const {
  if (!tiled) return y / strip_rows();
  const std::uint32_t across = static_cast<std::uint32_t>(ceil_div(width, tile_width));
  return y / tile_height * across + x / tile_width;
}

namespace {

// Strips (or tiles) a page of this size has; 0 for an empty page or tile. Saturates at the
// largest uint64 for absurd sizes.
std::uint64_t chunk_count(const TiffDirectory& directory) {
  if (directory.width == 0 || directory.height == 0) return 0;
  if (!directory.tiled) return ceil_div(directory.height, directory.strip_rows());
  if (directory.tile_width == 0 || directory.tile_height == 0) return 0;
  return saturating_product(ceil_div(directory.width, directory.tile_width),
                            ceil_div(directory.height, directory.tile_height));
}

}  // namespace

TiffDirectoryReader::TiffDirectoryReader(const std::string& path) : path_(path) {
  // A regular file only: a TIFF's directories may be anywhere in it, which a pipe cannot give.
  file_ = std::make_unique<RawFile>(path, "a TIFF file", nullptr, FileKinds::only_regular);
  file_bytes_ = file_->size_bytes();
  const std::string not_tiff = "cannot read as TIFF: ";
  unsigned char header[16] = {};
  if (file_bytes_ < 8) {
    throw Error(path_, not_tiff + "the file is " + std::to_string(file_bytes_) +
                           " bytes, shorter than a TIFF header");
  }
  file_->read_at(0, header, std::min<std::uint64_t>(file_bytes_, sizeof header));
  if (header[0] == 'I' && header[1] == 'I') {
    big_endian_ = false;
  } else if (header[0] == 'M' && header[1] == 'M') {
    big_endian_ = true;
  } else {
    throw Error(path_, not_tiff + "it does not start with II or MM (not a TIFF file)");
  }
  byte_swapped_ = big_endian_ != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__);
  const std::uint64_t version = unsigned_at(header + 2, 2);
  if (version == 42) {
    next_directory_ = unsigned_at(header + 4, 4);
  } else if (version == 43) {
    if (file_bytes_ < 16 || unsigned_at(header + 4, 2) != 8 || unsigned_at(header + 6, 2) != 0) {
      throw Error(path_, not_tiff + "its BigTIFF header is damaged");
    }
    big_tiff_ = true;
    next_directory_ = unsigned_at(header + 8, 8);
  } else {
    throw Error(path_, not_tiff + "its version is " + std::to_string(version) +
                           ", not 42 (TIFF) or 43 (BigTIFF)");
  }
  if (next_directory_ == 0) throw Error(path_, not_tiff + "it has no pages");
}

TiffDirectoryReader::~TiffDirectoryReader() = default;

std::uint64_t TiffDirectoryReader::unsigned_at(const unsigned char* at, unsigned bytes) const {
  std::uint64_t value = 0;
  for (unsigned i = 0; i < bytes; ++i) {
    const unsigned shift = 8 * (big_endian_ ? bytes - 1 - i : i);
    value |= std::uint64_t{at[i]} << shift;
  }
  return value;
}

bool TiffDirectoryReader::next(TiffDirectory* page) {
  if (next_directory_ == 0) return false;
  directory_offset_ = next_directory_;
  try {
    read_directory(next_directory_, page);
  } catch (const std::bad_alloc&) {
    // Arrays of offsets and counts are as long as the file lets them be.
    throw Error(path_,
                "out of memory reading the directory of page " + std::to_string(pages_read_ + 1));
  }
  ++pages_read_;
  return true;
}

void TiffDirectoryReader::go_to_directory(std::uint64_t offset, std::uint64_t pages_before) {
  next_directory_ = offset;
  pages_read_ = pages_before;
  // Loops are looked for afresh from here.
  kept_directory_ = 0;
  directories_until_kept_ = 1;
  keep_every_ = 1;
}

void TiffDirectoryReader::read_at(std::uint64_t offset, unsigned char* out, std::size_t bytes) {
  file_->read_at(offset, out, bytes);
}

bool TiffDirectoryReader::values_in_file(const Entry& entry) const {
  if (entry.values_in_field()) return true;
  const std::uint64_t bytes = entry.value_bytes();
  return entry.offset <= file_bytes_ &&
         file_bytes_ - entry.offset >= std::min<std::uint64_t>(bytes, kDescriptionBytes);
}

void TiffDirectoryReader::entry_bytes(const Entry& entry, std::uint64_t max_bytes,
                                      std::vector<unsigned char>* out, const std::string& where) {
  const std::uint64_t bytes = std::min(entry.value_bytes(), max_bytes);
  if (entry.values_in_field()) {
    out->assign(entry.field, entry.field + bytes);
    return;
  }
  if (entry.offset > file_bytes_ || file_bytes_ - entry.offset < bytes) {
    throw Error(path_, where + ": the values of its " + tag_name(entry.tag) +
                           " lie beyond the end of the file (truncated)");
  }
  out->resize(static_cast<std::size_t>(bytes));
  if (bytes > 0) file_->read_at(entry.offset, out->data(), static_cast<std::size_t>(bytes));
}

void TiffDirectoryReader::read_integers(const Entry& entry, std::uint64_t count,
                                        std::vector<std::uint64_t>* values,
                                        const std::string& where) {
  if (!is_integer(entry.type)) {
    throw Error(path_, where + ": its " + std::string(tag_name(entry.tag)) + " has field type " +
                           std::to_string(entry.type) + ", not an integer type");
  }
  const unsigned size = type_bytes(entry.type);
  std::vector<unsigned char>& bytes = scratch_;
  entry_bytes(entry, saturating_product(count, size), &bytes, where);
  values->resize(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < values->size(); ++i) {
    const std::uint64_t value = unsigned_at(bytes.data() + i * size, size);
    const bool negative = is_signed(entry.type) && (value >> (8 * size - 1)) != 0;
    if (negative) {
      throw Error(path_,
                  where + ": its " + std::string(tag_name(entry.tag)) + " holds a negative value");
    }
    (*values)[i] = value;
  }
}

std::uint64_t TiffDirectoryReader::integer(const Entry& entry, std::uint64_t max,
                                           const std::string& where) {
  if (entry.count == 0) {
    throw Error(path_, where + ": its " + std::string(tag_name(entry.tag)) + " holds no value");
  }
  read_integers(entry, 1, &one_value_, where);
  if (one_value_[0] > max) {
    throw Error(path_, where + ": its " + std::string(tag_name(entry.tag)) + " is " +
                           std::to_string(one_value_[0]) + ", more than " + std::to_string(max));
  }
  return one_value_[0];
}

float TiffDirectoryReader::rational(const Entry& entry, const std::string& where) {
  if (entry.count == 0) return 0;
  std::vector<unsigned char> bytes;
  entry_bytes(entry, type_bytes(entry.type), &bytes, where);
  switch (entry.type) {
    case kRational:
    case kSignedRational: {
      std::uint64_t numerator = unsigned_at(bytes.data(), 4);
      std::uint64_t denominator = unsigned_at(bytes.data() + 4, 4);
      double n = static_cast<double>(numerator), d = static_cast<double>(denominator);
      if (entry.type == kSignedRational) {
        n = static_cast<std::int32_t>(numerator);
        d = static_cast<std::int32_t>(denominator);
      }
      return n == 0 || d == 0 ? 0.0f : static_cast<float>(n / d);
    }
    case kFloat: {
      const std::uint32_t bits = static_cast<std::uint32_t>(unsigned_at(bytes.data(), 4));
      float value;
      std::memcpy(&value, &bits, sizeof value);
      return value;
    }
    case kDouble: {
      const std::uint64_t bits = unsigned_at(bytes.data(), 8);
      double value;
      std::memcpy(&value, &bits, sizeof value);
      // Beyond float's range the conversion is undefined: such a resolution reads as absent.
      return std::fabs(value) <= std::numeric_limits<float>::max() ? static_cast<float>(value)
                                                                   : 0.0f;
    }
    default: {
      // An integer; a negative one, or another type, reads as absent.
      if (!is_integer(entry.type)) return 0;
      const unsigned size = type_bytes(entry.type);
      const std::uint64_t value = unsigned_at(bytes.data(), size);
      if (is_signed(entry.type) && (value >> (8 * size - 1)) != 0) return 0;
      return static_cast<float>(value);
    }
  }
}

std::string TiffDirectoryReader::text(const Entry& entry, const std::string& where) {
  if (entry.type != kAscii && entry.type != kByte && entry.type != kUndefined) return "";
  std::vector<unsigned char> bytes;
  entry_bytes(entry, kDescriptionBytes, &bytes, where);
  const auto end = std::find(bytes.begin(), bytes.end(), '\0');
  return std::string(bytes.begin(), end);
}

void TiffDirectoryReader::read_directory(std::uint64_t offset, TiffDirectory* page) {
  const std::string where = "cannot read the directory of page " + std::to_string(pages_read_ + 1);
  if (offset == kept_directory_) {
    throw Error(path_, where + ": it is an earlier page's (the directories loop)");
  }
  if (--directories_until_kept_ == 0) {
    kept_directory_ = offset;
    keep_every_ *= 2;
    directories_until_kept_ = keep_every_;
  }
  const unsigned count_bytes = big_tiff_ ? 8 : 2;
  const unsigned entry_size = big_tiff_ ? 20 : 12;
  const unsigned field_bytes = big_tiff_ ? 8 : 4;
  if (offset > file_bytes_ || file_bytes_ - offset < count_bytes) {
    throw Error(path_, where + ": it would start at byte " + std::to_string(offset) +
                           ", but the file is " + std::to_string(file_bytes_) +
                           " bytes (truncated)");
  }
  // One read for the entry count and, most often, the entries: directories of up to 40
  // entries (writers store 10 to 20) are read whole in it, half the system calls of reading
  // the count first.
  std::vector<unsigned char>& table = directory_;
  const std::uint64_t first_read = std::min<std::uint64_t>(file_bytes_ - offset, kFirstRead);
  table.resize(static_cast<std::size_t>(first_read));
  file_->read_at(offset, table.data(), table.size());
  const std::uint64_t entries = unsigned_at(table.data(), count_bytes);
  if (entries > kMostEntries) {
    throw Error(path_, where + ": it claims " + std::to_string(entries) +
                           " entries, more than 4096 (not a directory)");
  }
  const std::uint64_t table_bytes = entries * entry_size + field_bytes;  // with the next offset
  if (file_bytes_ - offset - count_bytes < table_bytes) {
    throw Error(path_, where + ": its " + std::to_string(entries) +
                           " entries run past the end of the file (truncated)");
  }
  if (count_bytes + table_bytes > table.size()) {
    table.resize(static_cast<std::size_t>(count_bytes + table_bytes));
    file_->read_at(offset + first_read, table.data() + first_read,
                   table.size() - static_cast<std::size_t>(first_read));
  }
  table.erase(table.begin(), table.begin() + count_bytes);

  // Reset to TIFF's defaults, keeping the arrays' memory for the next page.
  std::vector<std::uint64_t> offsets_memory = std::move(page->chunk_offsets);
  std::vector<std::uint64_t> bytes_memory = std::move(page->chunk_bytes);
  *page = TiffDirectory{};
  page->chunk_offsets = std::move(offsets_memory);
  page->chunk_bytes = std::move(bytes_memory);
  page->chunk_offsets.clear();
  page->chunk_bytes.clear();
  Entry offsets, byte_counts, tile_offsets, tile_byte_counts;
  bool has_tile_size = false, has_rows_per_strip = false;
  std::bitset<65536> seen;  // a tag's later entries are ignored, as libtiff ignores them
  for (std::uint64_t i = 0; i < entries; ++i) {
    const unsigned char* at = table.data() + i * entry_size;
    Entry entry;
    entry.tag = static_cast<std::uint16_t>(unsigned_at(at, 2));
    if (seen[entry.tag]) continue;
    seen[entry.tag] = true;
    entry.type = static_cast<std::uint16_t>(unsigned_at(at + 2, 2));
    entry.count = unsigned_at(at + 4, big_tiff_ ? 8 : 4);
    entry.field_bytes = field_bytes;
    std::memcpy(entry.field, at + entry_size - field_bytes, field_bytes);
    entry.offset = unsigned_at(entry.field, field_bytes);
    entry.present = true;
    constexpr std::uint64_t k16 = 0xffff, k32 = 0xffffffff;
    switch (entry.tag) {
      case kImageWidth: page->width = static_cast<std::uint32_t>(integer(entry, k32, where)); break;
      case kImageLength:
        page->height = static_cast<std::uint32_t>(integer(entry, k32, where));
        break;
      case kBitsPerSample:
        page->bits_per_sample = static_cast<std::uint16_t>(integer(entry, k16, where));
        break;
      case kCompression:
        page->compression = static_cast<std::uint16_t>(integer(entry, k16, where));
        break;
      case kPhotometric:
        page->photometric = static_cast<std::uint16_t>(integer(entry, k16, where));
        break;
      case kFillOrder:
        page->fill_order = static_cast<std::uint16_t>(integer(entry, k16, where));
        break;
      case kSamplesPerPixel:
        page->samples_per_pixel = static_cast<std::uint16_t>(integer(entry, k16, where));
        break;
      case kRowsPerStrip:
        page->rows_per_strip = static_cast<std::uint32_t>(integer(entry, k32, where));
        has_rows_per_strip = true;
        break;
      case kPredictor:
        page->predictor = static_cast<std::uint16_t>(integer(entry, k16, where));
        break;
      case kSampleFormat:
        page->sample_format = static_cast<std::uint16_t>(integer(entry, k16, where));
        break;
      case kTileWidth:
        page->tile_width = static_cast<std::uint32_t>(integer(entry, k32, where));
        has_tile_size = true;
        break;
      case kTileLength:
        page->tile_height = static_cast<std::uint32_t>(integer(entry, k32, where));
        has_tile_size = true;
        break;
      // Tags mvox could do without: damaged, they read as absent, as libtiff reads them.
      case kImageDescription:
        if (values_in_file(entry)) page->description = text(entry, where);
        break;
      case kXResolution:
        if (values_in_file(entry)) page->x_resolution = rational(entry, where);
        break;
      case kYResolution:
        if (values_in_file(entry)) page->y_resolution = rational(entry, where);
        break;
      case kStripOffsets: offsets = entry; break;
      case kStripByteCounts: byte_counts = entry; break;
      case kTileOffsets: tile_offsets = entry; break;
      case kTileByteCounts: tile_byte_counts = entry; break;
      default: break;  // a tag mvox does not look at
    }
  }
  next_directory_ = unsigned_at(table.data() + entries * entry_size, field_bytes);

  page->tiled = has_tile_size || tile_offsets.present;
  if (page->tiled) {
    offsets = tile_offsets;
    byte_counts = tile_byte_counts;
  } else if (!has_rows_per_strip) {
    page->rows_per_strip = page->height;
  }
  const std::uint64_t chunks = chunk_count(*page);
  if (chunks == 0) return;  // an empty page or tile, which the stack refuses by its sizes
  if (chunks > 0xffffffffu) {
    throw Error(path_, where + ": it would have " + std::to_string(chunks) + " " +
                           (page->tiled ? "tiles" : "strips") + ", more than 2^32-1");
  }
  const char* chunk_kind = page->tiled ? "tile" : "strip";
  const std::string offsets_name = page->tiled ? "TileOffsets" : "StripOffsets";
  if (!offsets.present) throw Error(path_, where + ": it has no " + offsets_name);
  if (offsets.count < chunks) {
    throw Error(path_, where + ": its " + offsets_name + " hold " + std::to_string(offsets.count) +
                           " values, but the page has " + std::to_string(chunks) + " " +
                           chunk_kind + "s");
  }
  read_integers(offsets, chunks, &page->chunk_offsets, where);
  if (byte_counts.present) {
    if (byte_counts.count < chunks) {
      throw Error(path_, where + ": its " + tag_name(byte_counts.tag) + " hold " +
                             std::to_string(byte_counts.count) + " values, but the page has " +
                             std::to_string(chunks) + " " + chunk_kind + "s");
    }
    read_integers(byte_counts, chunks, &page->chunk_bytes, where);
    return;
  }
  // Uncompressed data are their samples: a writer may leave out their byte counts.
  if (page->compression != 1) {
    throw Error(path_,
                where + ": it has no " + (page->tiled ? "TileByteCounts" : "StripByteCounts"));
  }
  const std::uint64_t pixel_bytes =
      ceil_div(saturating_product(page->bits_per_sample, page->samples_per_pixel), 8);
  page->chunk_bytes.resize(page->chunk_offsets.size());
  for (std::size_t i = 0; i < page->chunk_bytes.size(); ++i) {
    std::uint64_t samples;
    if (page->tiled) {
      samples = saturating_product(page->tile_width, page->tile_height);
    } else {
      const std::uint64_t first_row = std::uint64_t{i} * page->strip_rows();
      samples = saturating_product(
          page->width, std::min<std::uint64_t>(page->strip_rows(), page->height - first_row));
    }
    page->chunk_bytes[i] = saturating_product(samples, pixel_bytes);
  }
}

}  // namespace mvox
