#pragma once
// The commonest PNG slice, 8- or 16-bit grey and not interlaced, decoded without libpng's row
// loop. libpng inflates one row per zlib call; for rows of 257 bytes or fewer (a 256-wide 8-bit
// slice and its filter byte) zlib never takes its fast path, which needs 258 bytes of room, and
// decoding such a stack took most of a run (MRbrain: 50-70 ms of 80-120). Here the image data
// is inflated into a buffer of many rows at once and the rows are unfiltered (PNG's five
// filters) as they come.
//
// Only regular files take this path: every chunk's length within the file, chunk types of
// letters, IHDR first with its CRC, the IDAT chunks together and their CRCs, no critical chunk
// but IHDR, IDAT and IEND, the zlib stream ending exactly where the last row does and at the end
// of an IDAT chunk, no IDAT after it, and IEND empty with its CRC. Anything else returns false
// and the file goes to libpng (png_slice_decoder.h), which refuses it or reads it as it did
// before this decoder; the samples of a file read here are those libpng gives
// (tests/host/png_plain_decoder_test.cpp, fuzz/png_slice_decoder_fuzzer.cpp).
#include <cstddef>

#include "read/image_stack/png_slice_decoder.h"

namespace mvox {

// Decodes `bytes` (`size` bytes) into `destination` when it is a regular 8- or 16-bit grey,
// non-interlaced PNG (above); 16-bit samples come out in native byte order. Returns false, when
// it is not, before or after calling `destination` (which may then be called again by the
// caller's other decoder). May throw what `destination` throws, or std::bad_alloc. Keeps the
// rows it inflates into, 64 KiB and a row, per thread between calls; more than 1 MiB (rows of
// over half a mebibyte) is given back after each call.
// With PngCrcs::checked_already the caller has checked every chunk's CRC up to IEND
// (image_file_check.h does for image stacks), and they are not computed twice.
bool decode_plain_grey_png(const unsigned char* bytes, std::size_t size,
                           const PngDestination& destination, PngCrcs crcs = PngCrcs::check);

}  // namespace mvox
