#pragma once
// The C interface of the image codecs module, libmvox_image_codecs.so: the only code that links
// OpenCV's imgcodecs. mvox decodes PNG (libpng) and JPEG (libjpeg) slices and writes PNG
// pictures itself; this module decodes every other format OpenCV reads (TIFF slices among
// PNGs, BMP, PNM, ...), and writes pictures of other types (.pgm, .tif, .bmp, .jpg).
// Loaded on demand by modules/image_codecs.h; see modules/module_loader.h for why C.
// Every function may be called from any thread, one call at a time per thread.
#include <stddef.h>

#if defined(__GNUC__)
#define MVOX_IMAGE_CODECS_EXPORT __attribute__((visibility("default")))
#else
#define MVOX_IMAGE_CODECS_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

// Bumped whenever a signature or a contract below changes.
#define MVOX_IMAGE_CODECS_API_VERSION 1

// Sample kinds of a decoded image.
enum {
  MVOX_IMAGE_U8 = 0,
  MVOX_IMAGE_S8 = 1,
  MVOX_IMAGE_U16 = 2,
  MVOX_IMAGE_S16 = 3,
  MVOX_IMAGE_S32 = 4,
  MVOX_IMAGE_F32 = 5,
  MVOX_IMAGE_F64 = 6,
  MVOX_IMAGE_OTHER = 7
};

typedef struct {
  int width;
  int height;
  int channels;
  int depth;  // MVOX_IMAGE_*
} mvox_image_shape;

// Where a decoded image goes: returns the address of width * height * channels samples, rows
// packed, or NULL to refuse the image (the caller keeps its own reason). Must not throw.
typedef unsigned char* (*mvox_image_destination)(void* context, const mvox_image_shape* shape);

// Receives encoded bytes, in order. Returns 0, or -1 to stop the encoding. Must not throw.
typedef int (*mvox_image_sink)(void* context, const unsigned char* bytes, size_t size);

// Returns MVOX_IMAGE_CODECS_API_VERSION as the module was built.
MVOX_IMAGE_CODECS_EXPORT int mvox_image_codecs_api_version(void);

// Makes OpenCV register its codecs now rather than at the first image: that costs about 10 MiB
// of resident memory (Debian's OpenCV registers GDAL's drivers), which mvox counts as the
// program's before it plans a run's memory.
MVOX_IMAGE_CODECS_EXPORT void mvox_image_codecs_initialize(void);

// Decodes the image file `bytes` (`size` bytes, at most INT_MAX) keeping its depth and its
// channels (OpenCV's IMREAD_ANYDEPTH | IMREAD_ANYCOLOR), and copies it to `destination`.
// Returns 0 when decoded and copied; 1 when `destination` refused the image; -1 when it cannot be
// decoded, with a one-line problem in `error` (`error_bytes` long, always terminated), such as
// "cannot decode image: REASON". Nothing is written on standard error: OpenCV's messages
// there are captured, and the reason taken from them.
MVOX_IMAGE_CODECS_EXPORT int mvox_image_decode(const unsigned char* bytes, size_t size,
                                               mvox_image_destination destination, void* context,
                                               char* error, size_t error_bytes);

// 1 when OpenCV can write images named with `extension` (".tif"), else 0.
MVOX_IMAGE_CODECS_EXPORT int mvox_image_can_write(const char* extension);

// Encodes a one-channel image of `width` x `height` samples, 8-bit (`bits` 8) or 16-bit
// unsigned (`bits` 16), rows `row_stride_bytes` apart, as the type `extension` names, and hands
// the bytes to `sink`. Returns 0, or -1 when OpenCV cannot encode it or `sink` stopped.
MVOX_IMAGE_CODECS_EXPORT int mvox_image_encode(const char* extension, const void* samples,
                                               int width, int height, size_t row_stride_bytes,
                                               int bits, mvox_image_sink sink, void* context);

#ifdef __cplusplus
}
#endif
