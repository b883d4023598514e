#pragma once
// Test support: PNG files written by libpng itself into memory, for the decoders' tests to read
// what real writers produce. Header-only, for the tests that link libpng.
#include <gtest/gtest.h>
#include <png.h>

#include <csetjmp>
#include <functional>
#include <vector>

namespace mvox::test {

// The file libpng writes when `write` (given the write and info structs, the output set up)
// sets the header and chunks and writes the rows; the file is ended here. A libpng error fails
// the test and gives an empty file. `write` should own no objects with destructors: an error
// leaves it by longjmp.
inline std::vector<unsigned char> png_written_by_libpng(
    const std::function<void(png_structp, png_infop)>& write) {
  std::vector<unsigned char> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    ADD_FAILURE() << "libpng could not write the test image";
    png_destroy_write_struct(&png, &info);
    return {};
  }
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t count) {
        auto* bytes = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(p));
        bytes->insert(bytes->end(), data, data + count);
      },
      nullptr);
  write(png, info);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return out;
}

}  // namespace mvox::test
