#pragma once
// Checks that a PNG or JPEG file is complete and intact before a decoder sees it.
//
// Why: libpng reports a truncated or corrupt file by printing "libpng error: ..." on standard
// error before OpenCV gives up, which breaks mvox's one-line errors; and libjpeg decodes a
// truncated JPEG with a warning on standard error and a grey bottom, which OpenCV returns as a
// good image: a silently wrong slice. Neither library lets OpenCV's caller replace its
// messages, so mvox looks at the file's structure first and refuses it with a message of its
// own. Other formats are left to their decoders (OpenCV's BMP and PNM readers and its libtiff
// handlers print nothing when mvox silences OpenCV's log).
#include <cstddef>
#include <string>

namespace mvox {

// The problem with the image file `bytes` (`size` bytes), or "" when there is none we can see:
// - PNG (by its 8-byte signature): every chunk must fit in the file with its CRC-32 correct,
//   the first must be IHDR and the last IEND; bytes after IEND are ignored, as libpng does.
// - JPEG (starting FF D8 FF): the file must end with the end-of-image marker FF D9 (trailing
//   zero bytes, which some writers pad with, are allowed).
// - Anything else: "".
// Never reads outside [bytes, bytes + size).
std::string image_file_problem(const unsigned char* bytes, std::size_t size);

}  // namespace mvox
