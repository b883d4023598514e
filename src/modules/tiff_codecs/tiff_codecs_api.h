#pragma once
// The C interface of the TIFF module, libmvox_tiff_codecs.so: the only code that links libtiff.
// Debian's libtiff brings seven codec libraries with it (WebP, Zstandard, LZMA, LERC, JBIG,
// libdeflate, JPEG), whose loading and relocation cost every mvox process about a millisecond,
// half its start-up beyond a hello-world's. So the TIFF reader (read/tiff/tiff_stack_source.h)
// reads the directories, uncompressed data and deflate data itself, keeps every decision (what
// a page may be, what its sizes may claim, the deflate check), and loads this module only for
// pages whose data only libtiff decodes (LZW, PackBits, JPEG, ..., and deflate with the
// floating-point predictor). The module walks its own copy of the directories, whose tags the
// reader compares with its own before trusting libtiff's decoding.
// The tag values exchanged (compression, photometric, sample format, ...) are TIFF's own
// numbers, as <tiff.h> names them. See modules/module_loader.h for why C.
// A handle is used by one thread at a time; different handles may be used on different threads.
#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__)
#define MVOX_TIFF_CODECS_EXPORT __attribute__((visibility("default")))
#else
#define MVOX_TIFF_CODECS_EXPORT
#endif

#ifdef __cplusplus
extern "C" {
#endif

// Bumped whenever a signature or a contract below changes.
#define MVOX_TIFF_CODECS_API_VERSION 3

// An open TIFF file with its current directory (page), and the first error libtiff reported
// on it since the last mvox_tiff_take_error(). libtiff's warnings are dropped (unknown tags are
// common and harmless) and nothing is printed on standard error.
typedef struct mvox_tiff mvox_tiff;

// The tags of the current directory, as libtiff reads them, that the reader compares with its
// own reading (tiff_directory.h). Absent tags read as TIFF's defaults, except photometric,
// whose absence reads as min-is-black (as most readers do).
typedef struct {
  uint32_t width;
  uint32_t height;
  uint16_t samples_per_pixel;
  uint16_t bits_per_sample;
  uint16_t sample_format;
  uint16_t photometric;
  uint16_t compression;
  uint16_t fill_order;
  uint16_t predictor;
  int byte_swapped;         // the file's byte order is not the machine's
  int tiled;                // tiles, not strips
  uint32_t tile_width;      // 0 when striped or absent
  uint32_t tile_height;     // 0 when striped or absent
  uint32_t rows_per_strip;  // as stored (defaulted); striped pages
  uint32_t chunks;          // strips or tiles
} mvox_tiff_page;

// Returns MVOX_TIFF_CODECS_API_VERSION as the module was built.
MVOX_TIFF_CODECS_EXPORT int mvox_tiff_codecs_api_version(void);

// 1 when this libtiff decodes TIFF's Compression value `compression`, 0 when not.
MVOX_TIFF_CODECS_EXPORT int mvox_tiff_codec_configured(uint16_t compression);

// Opens `path` for reading with read(2), not a memory map (so that streaming a large file does
// not grow the process's resident memory with pages already used), and reads its first
// directory. Returns NULL when it cannot, with libtiff's first message (or "out of memory", or
// "") in `error` (`error_bytes` long, always terminated).
MVOX_TIFF_CODECS_EXPORT mvox_tiff* mvox_tiff_open(const char* path, char* error,
                                                  size_t error_bytes);

MVOX_TIFF_CODECS_EXPORT void mvox_tiff_close(mvox_tiff* tiff);

// Writes the first error libtiff reported since the last call into `error` (`error_bytes`
// long, always terminated; one line; "" when none) and forgets it.
MVOX_TIFF_CODECS_EXPORT void mvox_tiff_take_error(mvox_tiff* tiff, char* error, size_t error_bytes);

// Moves to the next directory: 1 when read; 0 after the last one, or when it cannot be read
// (then an error is reported, see mvox_tiff_take_error).
MVOX_TIFF_CODECS_EXPORT int mvox_tiff_read_directory(mvox_tiff* tiff);

// Reads the directory at byte `offset` of the file (one the reader found itself), so that a
// slab worker starting inside a stack need not read every directory before it: 1 when read, 0
// when not (then an error is reported).
MVOX_TIFF_CODECS_EXPORT int mvox_tiff_read_directory_at(mvox_tiff* tiff, uint64_t offset);

MVOX_TIFF_CODECS_EXPORT void mvox_tiff_page_tags(mvox_tiff* tiff, mvox_tiff_page* page);

// Where strip or tile `index` of the current page is stored: 1 with its file offset and stored
// byte count, 0 when the directory cannot say.
MVOX_TIFF_CODECS_EXPORT int mvox_tiff_chunk_location(mvox_tiff* tiff, uint32_t index,
                                                     uint64_t* offset, uint64_t* bytes);

// Decodes strip or tile `index` into out[0, out_bytes): the decoded byte count, or -1.
MVOX_TIFF_CODECS_EXPORT int64_t mvox_tiff_read_chunk(mvox_tiff* tiff, uint32_t index, void* out,
                                                     int64_t out_bytes);

// Decodes the stored bytes of strip or tile `index`, given in `stored` (bits in stored order),
// into out[0, out_bytes) as mvox_tiff_read_chunk would: 1 when decoded, 0 when not.
MVOX_TIFF_CODECS_EXPORT int mvox_tiff_decode_stored_chunk(mvox_tiff* tiff, uint32_t index,
                                                          void* stored, int64_t stored_bytes,
                                                          void* out, int64_t out_bytes);

// Makes libtiff inflate the current page's deflate data with zlib rather than libdeflate: 1
// when it will. (libtiff takes libdeflate's "insufficient space" as success, for writers that
// store more rows than a strip holds, but libdeflate leaves the end of the output unwritten
// then; zlib fills it exactly.)
MVOX_TIFF_CODECS_EXPORT int mvox_tiff_inflate_with_zlib(mvox_tiff* tiff);

#ifdef __cplusplus
}
#endif
