#include "read/image_stack/png_slice_decoder.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <exception>

#include "error.h"
#include "read/image_stack/png_bytes.h"
#include "read/image_stack/png_plain_decoder.h"

namespace mvox {
namespace {

// Everything libpng's callbacks and the jump back need. Plain data only: libpng leaves a
// function by longjmp, which would skip the destructors of C++ objects in the frames between.
struct Decoding {
  const unsigned char* bytes;
  std::size_t size;
  std::size_t position;
  char error[200];
};

void read_bytes(png_structp png, png_bytep out, png_size_t count) {
  auto* decoding = static_cast<Decoding*>(png_get_io_ptr(png));
  if (count > decoding->size - decoding->position) png_error(png, "the file ends inside a chunk");
  std::memcpy(out, decoding->bytes + decoding->position, count);
  decoding->position += count;
}

void on_error(png_structp png, png_const_charp message) {
  auto* decoding = static_cast<Decoding*>(png_get_error_ptr(png));
  std::snprintf(decoding->error, sizeof decoding->error, "%s", message);
  png_longjmp(png, 1);
}

// Warnings concern ancillary chunks (an unknown one, a wrong sRGB profile); the samples are
// good, and libpng would print each on standard error.
void on_warning(png_structp, png_const_charp) {}

// PASS 1: the header. Returns false (with decoding->error set) when libpng fails.
bool read_header(png_structp png, png_infop info, png_uint_32* width, png_uint_32* height,
                 int* bit_depth, int* passes) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  int color_type = 0;
  png_get_IHDR(png, info, width, height, bit_depth, &color_type, nullptr, nullptr, nullptr);
  if (*bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);  // as OpenCV does
  if (*bit_depth == 16) {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    if (first == 1) png_set_swap(png);  // PNG stores 16-bit samples big-endian
  }
  *passes = png_set_interlace_handling(png);  // 7 for Adam7, else 1
  png_read_update_info(png, info);
  return true;
}

// PASS 2: the samples, `height` rows of `row_bytes` into `samples`, each row once per pass (as
// png_read_image does, but without its array of a pointer per row: 8 bytes a row, eight times
// the slice itself for a slice one 8-bit sample wide; found by fuzz/png_slice_decoder_fuzzer).
// Returns false when libpng fails.
bool read_rows(png_structp png, png_infop info, unsigned char* samples, std::size_t row_bytes,
               png_uint_32 height, int passes) {
  if (setjmp(png_jmpbuf(png))) return false;
  for (int pass = 0; pass < passes; ++pass)
    for (png_uint_32 y = 0; y < height; ++y) png_read_row(png, samples + y * row_bytes, nullptr);
  png_read_end(png, info);
  return true;
}

// libpng allocates a text chunk's declared length before reading it: a 95-byte file declaring
// 600 MB had it allocate 600 MB (found by fuzz/png_slice_decoder_fuzzer; image stacks check
// their files first, image_file_check.h, and never gave it one). A chunk before IEND that does
// not fit in the file is refused here, as reading it would be.
void check_chunk_lengths(const std::string& path, const unsigned char* bytes, std::size_t size) {
  std::size_t at = 8;
  while (size >= 8 && at <= size - 8) {
    const std::uint32_t length = png_uint32(bytes + at);
    if (length > size - at - 8 || size - at - 8 - length < 4)
      throw Error(path, "cannot decode PNG: the file ends inside a chunk");
    if (std::memcmp(bytes + at + 4, "IEND", 4) == 0) return;
    at += std::size_t{length} + 12;
  }
}

}  // namespace

bool is_plain_grey_png(const unsigned char* bytes, std::size_t size) {
  if (size < 8 + 25 || !has_png_signature(bytes, size)) return false;
  if (std::memcmp(bytes + 12, "IHDR", 4) != 0 || png_uint32(bytes + 8) != 13) return false;
  if (bytes[8 + 8 + 9] != 0) return false;  // colour type: 0 is grey without alpha
  // A tRNS chunk, which makes one grey value transparent, comes before the first IDAT.
  std::size_t at = 8;
  while (at + 8 <= size) {
    const std::uint32_t length = png_uint32(bytes + at);
    if (std::memcmp(bytes + at + 4, "tRNS", 4) == 0) return false;
    if (std::memcmp(bytes + at + 4, "IDAT", 4) == 0) return true;
    if (length > size - at - 8) return true;  // cut short: libpng says so
    at += std::size_t{length} + 12;
  }
  return true;
}

void decode_png_slice(const std::string& path, const unsigned char* bytes, std::size_t size,
                      const PngDestination& slice_destination, PngCrcs crcs) {
  // The destination is asked for once, whichever decoder asks (the same header gives both the
  // same size and type).
  unsigned char* slice = nullptr;
  const PngDestination destination = [&](std::uint32_t width, std::uint32_t height,
                                         SampleType type) {
    if (slice == nullptr) slice = slice_destination(width, height, type);
    return slice;
  };
  if (!decode_plain_grey_png(bytes, size, destination, crcs))
    decode_png_with_libpng(path, bytes, size, destination);
}

void decode_png_with_libpng(const std::string& path, const unsigned char* bytes, std::size_t size,
                            const PngDestination& destination) {
  check_chunk_lengths(path, bytes, size);
  Decoding decoding{bytes, size, 0, ""};
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &decoding, &on_error, &on_warning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    throw Error(path, "cannot decode PNG: libpng has no memory for its state");
  }
  // libpng's own limits (1,000,000 pixels a side by default) are lifted: the header was already
  // checked against mvox's (image_header.h), and a slice may be wider than libpng assumes.
  png_set_user_limits(png, 0x7fffffff, 0x7fffffff);
  // A compressed text or profile chunk is inflated whole: past the file's size and a mebibyte,
  // libpng skips it with a warning, so that a small file cannot make it inflate gigabytes.
  png_set_chunk_malloc_max(png, size + (std::size_t{1} << 20));
  png_set_read_fn(png, &decoding, &read_bytes);

  struct Cleanup {
    png_structp* png;
    png_infop* info;
    ~Cleanup() { png_destroy_read_struct(png, info, nullptr); }
  } cleanup{&png, &info};

  png_uint_32 width = 0, height = 0;
  int bit_depth = 0;
  int passes = 1;
  if (!read_header(png, info, &width, &height, &bit_depth, &passes))
    throw Error(path, std::string("cannot decode PNG: ") + decoding.error);
  const SampleType type = bit_depth == 16 ? SampleType::u16 : SampleType::u8;
  const std::size_t row_bytes = std::size_t{width} * sample_bytes(type);
  if (png_get_rowbytes(png, info) != row_bytes)
    throw Error(path, "cannot decode PNG: rows of " + std::to_string(png_get_rowbytes(png, info)) +
                          " bytes, expected " + std::to_string(row_bytes));
  unsigned char* samples = destination(width, height, type);
  if (!read_rows(png, info, samples, row_bytes, height, passes))
    throw Error(path, std::string("cannot decode PNG: ") + decoding.error);
}

}  // namespace mvox
