#pragma once
// The C interface of the DICOM module, libmvox_dicom_codecs.so: the only code that links GDCM.
// mvox reads DICOM headers with its own element walk (read/dicom/dicom_file_scan.h) and hands
// GDCM a file only to decode its pixel data; this module is that decoder, loaded on demand by
// read/dicom/dicom_pixel_reader.cpp. See modules/module_loader.h for why C.
#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__)
#define MVOX_DICOM_CODECS_EXPORT __attribute__((visibility("default")))
#else
#define MVOX_DICOM_CODECS_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

// Bumped whenever a signature or a contract below changes.
#define MVOX_DICOM_CODECS_API_VERSION 1

// The frame to decode and what mvox's own header walk found, which GDCM's image must match.
typedef struct {
  const char* path;
  uint32_t frame;   // 0-based
  uint32_t frames;  // NumberOfFrames: 1 reads the file whole, more reads one frame's region
  uint32_t columns;
  uint32_t rows;
  uint16_t bits_allocated;  // 8, 16 or 32
  int is_signed;            // PixelRepresentation
} mvox_dicom_frame;

// Returns MVOX_DICOM_CODECS_API_VERSION as the module was built.
MVOX_DICOM_CODECS_EXPORT int mvox_dicom_codecs_api_version(void);

// Decodes `frame` into `destination` (exactly `destination_bytes` = columns * rows *
// bits_allocated / 8 bytes: native byte order, rows packed). Returns 0 when decoded. Otherwise
// writes a one-line problem into `error` (`error_bytes` long, always terminated), without a
// final period and without the file's name, which the caller adds, and returns
//   -1 when GDCM cannot decode it: "GDCM cannot read the file", "frame 3", or "" when GDCM
//      gives no reason (the caller names the transfer syntax);
//   -2 when GDCM decodes an image unlike the header's: "GDCM decodes a 10x10 image where the
//      header says 12x10".
// GDCM's own messages on standard error are switched off.
MVOX_DICOM_CODECS_EXPORT int mvox_dicom_decode_frame(const mvox_dicom_frame* frame,
                                                     unsigned char* destination,
                                                     size_t destination_bytes, char* error,
                                                     size_t error_bytes);

// Writes GDCM's name of the transfer syntax `uid` ("JPEG 2000 Image Compression (Lossless
// Only)") into `name` (`name_bytes` long, always terminated), or "" when GDCM does not know it.
MVOX_DICOM_CODECS_EXPORT void mvox_dicom_transfer_syntax_name(const char* uid, char* name,
                                                              size_t name_bytes);

#ifdef __cplusplus
}
#endif
