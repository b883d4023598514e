#include "tiff_stack_files.h"

#include <algorithm>

namespace mvox::test::tiff_stack_files {

void write_page(TIFF* tiff, const void* pixels, std::uint32_t width, std::uint32_t height,
                std::uint16_t bits, std::uint16_t format, std::uint16_t samples_per_pixel,
                const Layout& layout, const std::function<void(TIFF*)>& extra) {
  TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, width);
  TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, height);
  TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, bits);
  TIFFSetField(tiff, TIFFTAG_SAMPLEFORMAT, format);
  TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, samples_per_pixel);
  TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC,
               samples_per_pixel == 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tiff, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tiff, TIFFTAG_COMPRESSION, layout.compression);
  if (extra) extra(tiff);
  const std::size_t pixel_bytes = std::size_t{bits} / 8 * samples_per_pixel;
  const auto* bytes = static_cast<const unsigned char*>(pixels);
  if (!layout.tiled) {
    TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, layout.rows_per_strip);
    std::vector<unsigned char> row(width * pixel_bytes);
    for (std::uint32_t y = 0; y < height; ++y) {
      std::copy(bytes + y * row.size(), bytes + (y + 1) * row.size(), row.begin());
      ASSERT_EQ(TIFFWriteScanline(tiff, row.data(), y, 0), 1);
    }
  } else {
    constexpr std::uint32_t kTile = 16;
    TIFFSetField(tiff, TIFFTAG_TILEWIDTH, kTile);
    TIFFSetField(tiff, TIFFTAG_TILELENGTH, kTile);
    std::vector<unsigned char> tile(kTile * kTile * pixel_bytes);
    for (std::uint32_t ty = 0; ty < height; ty += kTile) {
      for (std::uint32_t tx = 0; tx < width; tx += kTile) {
        std::fill(tile.begin(), tile.end(), 0xee);  // padding the reader must not copy
        for (std::uint32_t y = ty; y < std::min(ty + kTile, height); ++y)
          for (std::uint32_t x = tx; x < std::min(tx + kTile, width); ++x)
            std::copy_n(bytes + (std::size_t{y} * width + x) * pixel_bytes, pixel_bytes,
                        tile.begin() + ((y - ty) * kTile + (x - tx)) * pixel_bytes);
        ASSERT_GE(TIFFWriteTile(tiff, tile.data(), tx, ty, 0, 0), 0);
      }
    }
  }
  ASSERT_EQ(TIFFWriteDirectory(tiff), 1);
}

std::vector<unsigned char> filled(std::size_t size, unsigned char value) {
  return std::vector<unsigned char>(size, value);
}

}  // namespace mvox::test::tiff_stack_files
