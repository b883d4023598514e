#pragma once
// Writes one slice as a grayscale image file (PNG, TIFF or PGM by extension; 8- or 16-bit),
// all or nothing: the image is encoded in memory and committed through OutputFile.
#include <string>
#include <vector>

#include "mvox/slice.h"

namespace mvox {

// `slice` must be u8 or u16. Throws mvox::Error naming `path`.
void write_slice_image(const std::string& path, const SliceView& slice);

// The bytes of the image file write_slice_image() would write, for a caller that commits the
// file itself (say, together with others). Throws mvox::Error naming `path`.
std::vector<unsigned char> encode_slice_image(const std::string& path, const SliceView& slice);

// Makes OpenCV register its image codecs now. It does so on first use of any of them, and that
// costs about 10 MiB of resident memory (Debian's OpenCV registers GDAL's drivers with them):
// a run that will encode or decode through OpenCV calls this before its memory is planned, so
// that the plan's "program and libraries" line includes it (memory_plan.h).
void initialize_image_codecs();

// Throws mvox::Error naming `path` unless its extension names an image format mvox can write
// (.png, .pgm, .tif, .bmp, .jpg...): checked before a long run rather than after it. Standard
// output ("-", /dev/stdout), devices and pipes without an extension get PNG.
void check_image_extension(const std::string& path);

}  // namespace mvox
