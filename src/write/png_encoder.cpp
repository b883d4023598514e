#include "write/png_encoder.h"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "error.h"

namespace mvox {
namespace {

// What libpng's callbacks need. Plain data: libpng leaves by longjmp (see png_slice_decoder).
struct Encoding {
  std::vector<unsigned char>* out;
  bool out_of_memory;
  char error[200];
};

void write_bytes(png_structp png, png_bytep data, png_size_t count) {
  auto* encoding = static_cast<Encoding*>(png_get_io_ptr(png));
  try {
    encoding->out->insert(encoding->out->end(), data, data + count);
  } catch (...) {
    encoding->out_of_memory = true;  // jumping out of a handler would skip the exception's end
  }
  if (encoding->out_of_memory) png_error(png, "out of memory for the encoded picture");
}

void flush(png_structp) {}

void on_error(png_structp png, png_const_charp message) {
  auto* encoding = static_cast<Encoding*>(png_get_error_ptr(png));
  std::snprintf(encoding->error, sizeof encoding->error, "%s", message);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}

// Writes the image; returns false when libpng fails. No C++ object lives in this frame.
bool write_image(png_structp png, png_infop info, const SliceView& slice, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  const int bit_depth = slice.type == SampleType::u8 ? 8 : 16;
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  png_set_IHDR(png, info, slice.width, slice.height, bit_depth, PNG_COLOR_TYPE_GRAY,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bit_depth == 16) {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    if (first == 1) png_set_swap(png);  // native samples, big-endian in the file
  }
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

}  // namespace

std::vector<unsigned char> encode_png(const SliceView& slice) {
  if (slice.type != SampleType::u8 && slice.type != SampleType::u16)
    throw Error("PNG", std::string("cannot write ") + sample_type_name(slice.type) +
                           " samples as an image (only 8- and 16-bit)");
  std::vector<unsigned char> encoded;
  std::vector<png_bytep> rows(slice.height);
  for (std::uint32_t y = 0; y < slice.height; ++y)
    rows[y] = const_cast<png_bytep>(static_cast<const unsigned char*>(slice.samples) +
                                    std::size_t{y} * slice.row_stride_bytes);
  Encoding encoding{&encoded, false, ""};
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &encoding, &on_error, &on_warning);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    throw Error("PNG", "libpng has no memory for its state");
  }
  png_set_write_fn(png, &encoding, &write_bytes, &flush);
  const bool written = write_image(png, info, slice, rows.data());
  png_destroy_write_struct(&png, &info);
  if (!written) throw Error("PNG", std::string("cannot encode: ") + encoding.error);
  return encoded;
}

}  // namespace mvox
