#include "read/image_stack/image_header.h"

#include <cstring>
#include <vector>

#include "read/compression_bounds.h"
#include "read/file_bytes.h"
#include "read/image_stack/png_bytes.h"

namespace mvox {
namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 20;

std::uint32_t big_endian_32(const unsigned char* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3];
}
std::uint32_t big_endian_16(const unsigned char* p) { return std::uint32_t{p[0]} << 8 | p[1]; }
std::uint32_t little_endian_16(const unsigned char* p) { return p[0] | std::uint32_t{p[1]} << 8; }
std::uint32_t little_endian_32(const unsigned char* p) {
  return p[0] | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

// Bytes the zlib stream of a non-interlaced PNG decodes to: a filter byte and the packed
// samples of each row (an interlaced image needs a little more).
std::uint64_t png_filtered_bytes(const ImageHeader& header, unsigned samples_per_pixel,
                                 unsigned bit_depth) {
  const std::uint64_t row_bits = std::uint64_t{header.width} * samples_per_pixel * bit_depth;
  return std::uint64_t{header.height} * (1 + (row_bits + 7) / 8);
}

// PNG: the 13-byte IHDR right after the signature, then the chunks, counting IDAT bytes.
std::optional<ImageHeader> png_header(const unsigned char* bytes, std::size_t size) {
  if (size < 33 || std::memcmp(bytes + 12, "IHDR", 4) != 0 || big_endian_32(bytes + 8) != 13)
    return std::nullopt;
  ImageHeader header;
  header.format = ImageFormat::png;
  header.width = big_endian_32(bytes + 16);
  header.height = big_endian_32(bytes + 20);
  const unsigned bit_depth = bytes[24];
  const unsigned colour_type = bytes[25];
  if (header.width == 0 || header.height == 0) return std::nullopt;
  // Colour types: 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGB + alpha. OpenCV drops the
  // alpha of grey + alpha and expands a palette to colour.
  header.channels = colour_type == 0 || colour_type == 4 ? 1 : 3;
  header.type = bit_depth == 16 ? SampleType::u16 : SampleType::u8;
  static constexpr unsigned kSamplesPerPixel[7] = {1, 0, 3, 1, 2, 0, 4};
  if (colour_type > 6 || kSamplesPerPixel[colour_type] == 0) return std::nullopt;
  header.stream_bytes = png_filtered_bytes(header, kSamplesPerPixel[colour_type], bit_depth);
  for (std::size_t at = 33; size - at >= 12;) {
    const std::uint64_t length = big_endian_32(bytes + at);
    if (std::memcmp(bytes + at + 4, "IEND", 4) == 0 || length > size - at - 12) break;
    if (std::memcmp(bytes + at + 4, "IDAT", 4) == 0) header.encoded_bytes += length;
    at += 12 + static_cast<std::size_t>(length);
  }
  return header;
}

// JPEG: the marker segments up to the first start of frame (SOFn), which gives the size.
std::optional<ImageHeader> jpeg_header(const unsigned char* bytes, std::size_t size) {
  std::size_t at = 2;
  while (at + 4 <= size) {
    if (bytes[at] != 0xff) return std::nullopt;
    const unsigned marker = bytes[at + 1];
    if (marker == 0xff) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8)) {  // no length follows
      at += 2;
      continue;
    }
    const std::size_t length = big_endian_16(bytes + at + 2);
    const bool start_of_frame =
        marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (start_of_frame) {
      if (length < 8 || at + 10 > size) return std::nullopt;
      ImageHeader header;
      header.format = ImageFormat::jpeg;
      const unsigned precision = bytes[at + 4];
      header.height = big_endian_16(bytes + at + 5);
      header.width = big_endian_16(bytes + at + 7);
      header.channels = bytes[at + 9] == 1 ? 1 : 3;
      header.type = precision > 8 ? SampleType::u16 : SampleType::u8;
      // A height of 0 is given later by a DNL marker: not known from the header.
      if (header.width == 0 || header.height == 0) return std::nullopt;
      return header;
    }
    if (marker == 0xd9 || marker == 0xda || length < 2) return std::nullopt;
    at += 2 + length;
  }
  return std::nullopt;
}

// BMP: the info header after the 14-byte file header; a palette of greys decodes as grey.
std::optional<ImageHeader> bmp_header(const unsigned char* bytes, std::size_t size) {
  if (size < 26) return std::nullopt;
  const std::uint32_t info_size = little_endian_32(bytes + 14);
  ImageHeader header;
  header.format = ImageFormat::bmp;
  unsigned bit_count = 0;
  std::size_t palette_entry = 4;
  std::uint32_t colours_used = 0;
  if (info_size == 12) {  // OS/2 BITMAPCOREHEADER: 16-bit sizes, 3-byte palette entries
    header.width = little_endian_16(bytes + 18);
    header.height = little_endian_16(bytes + 20);
    bit_count = little_endian_16(bytes + 24);
    palette_entry = 3;
  } else if (info_size >= 40 && size >= 54) {
    const auto width = static_cast<std::int32_t>(little_endian_32(bytes + 18));
    const auto height = static_cast<std::int32_t>(little_endian_32(bytes + 22));
    if (width <= 0 || height == 0 || height == INT32_MIN) return std::nullopt;
    header.width = static_cast<std::uint32_t>(width);
    header.height = static_cast<std::uint32_t>(height < 0 ? -height : height);  // top-down
    bit_count = little_endian_16(bytes + 28);
    colours_used = little_endian_32(bytes + 46);
  } else {
    return std::nullopt;
  }
  if (header.width == 0 || header.height == 0) return std::nullopt;
  header.channels = 3;
  if (bit_count <= 8) {
    const std::uint64_t entries = colours_used != 0 ? colours_used : std::uint64_t{1} << bit_count;
    const std::size_t start = 14 + std::size_t{info_size};
    bool grey = entries <= 256 && start + entries * palette_entry <= size;
    for (std::uint64_t i = 0; grey && i < entries; ++i) {
      const unsigned char* entry = bytes + start + i * palette_entry;
      grey = entry[0] == entry[1] && entry[1] == entry[2];
    }
    if (grey) header.channels = 1;
  }
  return header;
}

// PNM: "P1".."P6", then width, height and (but for bitmaps) the largest value, as decimal
// numbers separated by white space and "#" comments.
std::optional<ImageHeader> pnm_header(const unsigned char* bytes, std::size_t size) {
  const unsigned kind = bytes[1] - '0';
  std::size_t at = 2;
  std::uint64_t numbers[3] = {0, 0, 0};
  const int wanted = kind == 1 || kind == 4 ? 2 : 3;
  for (int n = 0; n < wanted; ++n) {
    for (;;) {  // white space and comments
      if (at >= size) return std::nullopt;
      if (bytes[at] == '#') {
        while (at < size && bytes[at] != '\n' && bytes[at] != '\r') ++at;
      } else if (bytes[at] == ' ' || bytes[at] == '\t' || bytes[at] == '\n' || bytes[at] == '\r' ||
                 bytes[at] == '\v' || bytes[at] == '\f') {
        ++at;
      } else {
        break;
      }
    }
    if (bytes[at] < '0' || bytes[at] > '9') return std::nullopt;
    while (at < size && bytes[at] >= '0' && bytes[at] <= '9') {
      numbers[n] = numbers[n] * 10 + (bytes[at] - '0');
      if (numbers[n] > 0xffffffffu) return std::nullopt;
      ++at;
    }
  }
  ImageHeader header;
  header.format = ImageFormat::pnm;
  header.width = static_cast<std::uint32_t>(numbers[0]);
  header.height = static_cast<std::uint32_t>(numbers[1]);
  if (header.width == 0 || header.height == 0) return std::nullopt;
  header.channels = kind == 3 || kind == 6 ? 3 : 1;
  header.type = wanted == 3 && numbers[2] > 255 ? SampleType::u16 : SampleType::u8;
  return header;
}

}  // namespace

std::optional<ImageHeader> parse_image_header(const unsigned char* bytes, std::size_t size) {
  if (has_png_signature(bytes, size)) return png_header(bytes, size);
  if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff)
    return jpeg_header(bytes, size);
  if (size >= 2 && bytes[0] == 'B' && bytes[1] == 'M') return bmp_header(bytes, size);
  if (size >= 3 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '6')
    return pnm_header(bytes, size);
  return std::nullopt;
}

std::optional<ImageHeader> read_image_header(const std::string& path) {
  ReadBuffer bytes;
  read_file_bytes(path, bytes, kMaxHeaderBytes, FileKinds::only_regular);
  return parse_image_header(bytes.data(), bytes.size());
}

std::uint64_t decoded_image_bytes(const ImageHeader& header) {
  return std::uint64_t{header.width} * header.height * static_cast<unsigned>(header.channels) *
         sample_bytes(header.type);
}

std::string image_size_problem(const ImageHeader& header) {
  const std::uint64_t pixels = std::uint64_t{header.width} * header.height;
  const std::string size = std::to_string(header.width) + "x" + std::to_string(header.height);
  if (pixels > kMaxDecodedImagePixels)
    return "image is " + size + ", " + std::to_string(pixels) +
           " pixels: more than the 2^30 pixels an image slice may have (OpenCV's limit); store "
           "so large a volume as raw, NRRD or TIFF";
  if (header.format == ImageFormat::png &&
      !could_decode_to(header.encoded_bytes, kDeflateMaxRatio, header.stream_bytes))
    return "corrupt PNG: its " + std::to_string(header.encoded_bytes) +
           " bytes of image data cannot hold a " + size +
           " image (deflate expands at most 1032 to 1)";
  return {};
}

}  // namespace mvox
