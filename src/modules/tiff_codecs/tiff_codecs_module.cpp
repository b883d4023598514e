// The TIFF module: libtiff behind tiff_codecs_api.h. Built as libmvox_tiff_codecs.so and
// loaded only by runs that read a TIFF file.
#include <tiffio.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>

#include "modules/tiff_codecs/tiff_codecs_api.h"

struct mvox_tiff {
  TIFF* handle = nullptr;
  std::string error;  // the first error libtiff reported since the last take_error
};

namespace {

void copy_text(const std::string& text, char* out, size_t out_bytes) {
  if (out_bytes == 0) return;
  const size_t n = std::min(text.size(), out_bytes - 1);
  std::memcpy(out, text.data(), n);
  out[n] = '\0';
}

// libtiff reports problems through callbacks; these, registered for one handle only
// (TIFFOpenExt, libtiff 4.5), keep its first error, on one line, and drop warnings instead of
// letting libtiff print them.
int keep_first_error(TIFF*, void* user_data, const char*, const char* format, va_list arguments) {
  auto* tiff = static_cast<mvox_tiff*>(user_data);
  if (tiff->error.empty()) {
    char text[512];
    std::vsnprintf(text, sizeof text, format, arguments);
    tiff->error = text;
    std::replace(tiff->error.begin(), tiff->error.end(), '\n', ' ');
  }
  return 1;  // handled: libtiff's global handler does not print it
}

int drop_warning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

}  // namespace

extern "C" {

int mvox_tiff_codecs_api_version(void) { return MVOX_TIFF_CODECS_API_VERSION; }

int mvox_tiff_codec_configured(uint16_t compression) {
  return TIFFIsCODECConfigured(compression) ? 1 : 0;
}

mvox_tiff* mvox_tiff_open(const char* path, char* error, size_t error_bytes) {
  copy_text("", error, error_bytes);
  auto* tiff = new (std::nothrow) mvox_tiff;
  TIFFOpenOptions* options = tiff ? TIFFOpenOptionsAlloc() : nullptr;
  if (!options) {
    delete tiff;
    copy_text("out of memory", error, error_bytes);
    return nullptr;
  }
  TIFFOpenOptionsSetErrorHandlerExtR(options, keep_first_error, tiff);
  TIFFOpenOptionsSetWarningHandlerExtR(options, drop_warning, tiff);
  tiff->handle = TIFFOpenExt(path, "rm", options);
  TIFFOpenOptionsFree(options);
  if (!tiff->handle) {
    copy_text(tiff->error, error, error_bytes);
    delete tiff;
    return nullptr;
  }
  return tiff;
}

void mvox_tiff_close(mvox_tiff* tiff) {
  if (!tiff) return;
  if (tiff->handle) TIFFClose(tiff->handle);
  delete tiff;
}

void mvox_tiff_take_error(mvox_tiff* tiff, char* error, size_t error_bytes) {
  copy_text(tiff->error, error, error_bytes);
  tiff->error.clear();
}

int mvox_tiff_read_directory(mvox_tiff* tiff) { return TIFFReadDirectory(tiff->handle); }

int mvox_tiff_read_directory_at(mvox_tiff* tiff, uint64_t offset) {
  return TIFFSetSubDirectory(tiff->handle, offset);
}

void mvox_tiff_page_tags(mvox_tiff* tiff, mvox_tiff_page* page) {
  TIFF* t = tiff->handle;
  *page = mvox_tiff_page{};
  page->samples_per_pixel = 1;
  page->bits_per_sample = 1;
  page->sample_format = SAMPLEFORMAT_UINT;
  page->photometric = PHOTOMETRIC_MINISBLACK;  // left so when the tag is absent
  page->compression = COMPRESSION_NONE;
  page->fill_order = FILLORDER_MSB2LSB;
  page->predictor = PREDICTOR_NONE;
  TIFFGetField(t, TIFFTAG_IMAGEWIDTH, &page->width);
  TIFFGetField(t, TIFFTAG_IMAGELENGTH, &page->height);
  TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLESPERPIXEL, &page->samples_per_pixel);
  TIFFGetFieldDefaulted(t, TIFFTAG_BITSPERSAMPLE, &page->bits_per_sample);
  TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLEFORMAT, &page->sample_format);
  TIFFGetFieldDefaulted(t, TIFFTAG_COMPRESSION, &page->compression);
  TIFFGetField(t, TIFFTAG_PHOTOMETRIC, &page->photometric);
  TIFFGetFieldDefaulted(t, TIFFTAG_FILLORDER, &page->fill_order);
  TIFFGetFieldDefaulted(t, TIFFTAG_PREDICTOR, &page->predictor);
  page->byte_swapped = TIFFIsByteSwapped(t) != 0;
  page->tiled = TIFFIsTiled(t) != 0;
  if (page->tiled) {
    TIFFGetField(t, TIFFTAG_TILEWIDTH, &page->tile_width);
    TIFFGetField(t, TIFFTAG_TILELENGTH, &page->tile_height);
    page->chunks = TIFFNumberOfTiles(t);
  } else {
    page->rows_per_strip = page->height;
    TIFFGetFieldDefaulted(t, TIFFTAG_ROWSPERSTRIP, &page->rows_per_strip);
    page->chunks = TIFFNumberOfStrips(t);
  }
}

int mvox_tiff_chunk_location(mvox_tiff* tiff, uint32_t index, uint64_t* offset, uint64_t* bytes) {
  int error = 0;
  *offset = TIFFGetStrileOffsetWithErr(tiff->handle, index, &error);
  if (error) return 0;
  *bytes = TIFFGetStrileByteCountWithErr(tiff->handle, index, &error);
  return error ? 0 : 1;
}

int64_t mvox_tiff_read_chunk(mvox_tiff* tiff, uint32_t index, void* out, int64_t out_bytes) {
  TIFF* t = tiff->handle;
  return TIFFIsTiled(t) ? TIFFReadEncodedTile(t, index, out, static_cast<tmsize_t>(out_bytes))
                        : TIFFReadEncodedStrip(t, index, out, static_cast<tmsize_t>(out_bytes));
}

int mvox_tiff_decode_stored_chunk(mvox_tiff* tiff, uint32_t index, void* stored,
                                  int64_t stored_bytes, void* out, int64_t out_bytes) {
  return TIFFReadFromUserBuffer(tiff->handle, index, stored, static_cast<tmsize_t>(stored_bytes),
                                out, static_cast<tmsize_t>(out_bytes)) != 0;
}

int mvox_tiff_inflate_with_zlib(mvox_tiff* tiff) {
  return TIFFSetField(tiff->handle, TIFFTAG_DEFLATE_SUBCODEC, DEFLATE_SUBCODEC_ZLIB) ? 1 : 0;
}

}  // extern "C"
