#pragma once
// What a slice image file declares about itself, read from its header alone, before any
// decoder sees it: so that a stack's size and sample type, and the memory a run will take, are
// known without decoding a slice, and so that a header declaring a gigantic image is refused
// before a decoder allocates for it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "mvox/slice.h"

namespace mvox {

enum class ImageFormat : std::uint8_t { png, jpeg, bmp, pnm };

struct ImageHeader {
  ImageFormat format = ImageFormat::png;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int channels = 1;  // as decoded: 1 for grayscale (also grey + alpha, whose alpha is dropped)
  SampleType type = SampleType::u8;  // as decoded: u8 or u16 (1-, 2- and 4-bit grey give u8)
  // PNG only (0 otherwise): bytes of compressed image data in the file (all IDAT chunks), and
  // the bytes their zlib stream must decode to (a filter byte and the packed samples per row).
  std::uint64_t encoded_bytes = 0;
  std::uint64_t stream_bytes = 0;
};

// The header of the image file held in bytes [0, size), or nothing when it is none of the
// formats above (the caller then lets the decoder find out). Reads only what the header needs:
// PNG's IHDR (and the lengths of its IDAT chunks), JPEG's first SOFn segment, BMP's info header,
// PNM's magic, width, height and maximum value. Throws nothing; never reads outside `bytes`.
// A header that names a format but is malformed or cut short gives nothing too: the decoder
// then reports it (image_file_check.h has caught truncated PNG and JPEG files already).
std::optional<ImageHeader> parse_image_header(const unsigned char* bytes, std::size_t size);

// The header of the image file `path`, reading at most its first 1 MiB (where every header
// above lies, even JPEG's after large EXIF or ICC segments), or nothing as parse_image_header.
// Throws mvox::Error naming the file when it cannot be read.
std::optional<ImageHeader> read_image_header(const std::string& path);

// Decoded bytes of the image: width * height * channels * bytes per sample.
std::uint64_t decoded_image_bytes(const ImageHeader& header);

// OpenCV refuses to decode images of more than 2^30 pixels (CV_IO_MAX_IMAGE_PIXELS) with an
// assertion text; mvox says it first, in its own words.
constexpr std::uint64_t kMaxDecodedImagePixels = std::uint64_t{1} << 30;

// The problem with an image this large, or "": more than kMaxDecodedImagePixels pixels, or a
// PNG whose compressed data cannot hold what its header declares (compression_bounds.h).
std::string image_size_problem(const ImageHeader& header);

}  // namespace mvox
