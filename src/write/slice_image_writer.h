#pragma once
// Writes one slice as a grayscale image file (PNG, TIFF or PGM by extension; 8- or 16-bit),
// all or nothing: the image is encoded in memory and committed through OutputFile. PNG is
// encoded by mvox (png_encoder.h); other types by OpenCV, in its module (modules/image_codecs.h).
#include <string>
#include <vector>

#include "mvox/slice.h"

namespace mvox {

// `slice` must be u8 or u16. Throws mvox::Error naming `path`.
void write_slice_image(const std::string& path, const SliceView& slice);

// The bytes of the image file write_slice_image() would write, for a caller that commits the
// file itself (say, together with others). Throws mvox::Error naming `path`.
std::vector<unsigned char> encode_slice_image(const std::string& path, const SliceView& slice);
// Writes `encoded` (encode_slice_image's bytes) to `path`, all or nothing. Throws mvox::Error
// naming `path`.
void write_image_file(const std::string& path, const std::vector<unsigned char>& encoded);

// Loads OpenCV's image codecs now when a picture named `path` will be encoded through them (any
// type but PNG), so that their memory, about 10 MiB once registered (Debian's OpenCV registers
// GDAL's drivers with them), counts as the program's when the run's memory is planned
// (memory_plan.h). Throws mvox::Error(path, reason) when their module cannot be loaded.
void initialize_image_codecs(const std::string& path);

// Throws mvox::Error naming `path` unless its extension names an image format mvox can write
// (.png, .pgm, .tif, .bmp, .jpg...): checked before a long run rather than after it; any type
// but PNG loads OpenCV's module to ask it. Standard
// output ("-", /dev/stdout), devices and pipes without an extension get PNG.
void check_image_extension(const std::string& path);

}  // namespace mvox
