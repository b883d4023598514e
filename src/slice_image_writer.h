#pragma once
// Writes one slice as a grayscale image file (PNG, TIFF or PGM by extension; 8- or 16-bit),
// all or nothing: the image is encoded in memory and committed through OutputFile.
#include <string>

#include "mvox/slice.h"

namespace mvox {

// `slice` must be u8 or u16. Throws mvox::Error naming `path`.
void write_slice_image(const std::string& path, const SliceView& slice);

}  // namespace mvox
