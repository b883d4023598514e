#pragma once
// Decodes a JPEG slice strictly, with libjpeg directly rather than through OpenCV.
//
// Why: libjpeg counts damaged entropy-coded data as a warning, not an error: a scan cut short
// and closed with an end-of-image marker, or restart markers that are junk or out of order, make
// it print "Corrupt JPEG data: ..." on standard error, fill what it could not decode with grey,
// and return the image, which OpenCV hands back as good. A volume with a grey block in one
// slice is a wrong surface, so here every libjpeg warning is an error, and nothing libjpeg says
// reaches standard error.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace mvox {

// Where the samples of a `width` x `height` image go: the address of width * height bytes,
// rows packed. Called once per image, after its header is read and checked. May throw;
// std::bad_alloc becomes an mvox::Error naming the file and the bytes asked for.
using JpegDestination = std::function<unsigned char*(std::uint32_t width, std::uint32_t height)>;

// True when `bytes` (`size` bytes) start like a JPEG file: FF D8 FF.
bool is_jpeg_file(const unsigned char* bytes, std::size_t size);

// Decodes the JPEG file `bytes` (`size` bytes), read from `path`, as 8-bit grayscale samples
// into `destination(width, height)`: exactly the samples OpenCV's cv::imdecode gives for the
// same file (both use Debian's libjpeg with its default settings; EXIF orientation, which
// OpenCV applies, is ignored, as TIFF's Orientation is by TiffStackSource).
// Throws mvox::Error(path, problem), with nothing written on standard error, when:
// - libjpeg reports an error or any warning: "cannot decode JPEG: " and libjpeg's own text
//   (such as "Corrupt JPEG data: premature end of data segment");
// - the image has more than one component: "colour image (3 channels): convert to grayscale
//   first", as ImageStackSource says for other formats;
// - a sequential Huffman-coded image declares more samples than its file could code
//   (compression_bounds.h), which is refused before anything of that size is allocated;
// - memory runs out (the problem names the bytes asked for).
// Never reads outside [bytes, bytes + size). Safe to call from any one thread at a time per
// call (no shared state).
void decode_jpeg_slice(const std::string& path, const unsigned char* bytes, std::size_t size,
                       const JpegDestination& destination);

}  // namespace mvox
