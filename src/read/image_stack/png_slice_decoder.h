#pragma once
// Decodes grey PNG slices without OpenCV, so that a PNG stack (what scanners and pipelines
// export most) never loads it: OpenCV's image codecs cost a run ~140 ms and ~50 MiB before the
// first slice (modules/image_codecs.h). Regular 8- and 16-bit non-interlaced files, nearly every
// slice a scanner writes, are inflated and unfiltered by png_plain_decoder.h, several times
// faster than libpng's row-by-row loop; every other grey PNG, and any file that one finds
// irregular, is read by libpng.
//
// It gives exactly the samples OpenCV's cv::imdecode(IMREAD_ANYDEPTH | IMREAD_ANYCOLOR) gives
// for the same file (tests/host/png_slice_decoder_test.cpp compares them): 8- and 16-bit grey
// as they are (16-bit in native byte order), 1-, 2- and 4-bit grey scaled to 8 bits, interlaced
// or not. Other PNGs (colour, palette, grey with alpha or a transparent colour) are left to
// OpenCV, which decides how to read or refuse them as it always did.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "mvox/slice.h"

namespace mvox {

// Where a decoded slice goes: the address of width * height samples of `type` (u8 or u16),
// rows packed. Called once, after the header is read. May throw.
using PngDestination =
    std::function<unsigned char*(std::uint32_t width, std::uint32_t height, SampleType type)>;

// Whether a decoder checks the CRCs of the chunks it reads, or the caller has checked every
// chunk's CRC up to IEND already (image stacks do, image_file_check.h): computing them twice
// took 2-4% of a run on MRbrain's PNG slices.
enum class PngCrcs { check, checked_already };

// True when `bytes` (`size` bytes) are a PNG this decoder reads: the PNG signature, an IHDR of
// colour type 0 (grey) and no tRNS chunk before the image data. Reads only chunk headers.
bool is_plain_grey_png(const unsigned char* bytes, std::size_t size);

// Decodes the grey PNG `bytes` (`size` bytes), read from `path`, into `destination`, which is
// called once. Precondition: is_plain_grey_png(bytes, size). Throws mvox::Error(path, "cannot
// decode PNG: " + libpng's reason) when libpng finds an error; libpng's warnings (an unknown or
// damaged ancillary chunk) do not stop it, and nothing is written on standard error.
// `crcs`: PngCrcs::checked_already when the caller checked every chunk's CRC up to IEND.
void decode_png_slice(const std::string& path, const unsigned char* bytes, std::size_t size,
                      const PngDestination& destination, PngCrcs crcs = PngCrcs::check);

// decode_png_slice with libpng alone: what the fuzzer (fuzz/png_slice_decoder_fuzzer.cpp)
// compares the plain decoder's samples with. Before libpng sees the file, a chunk before IEND
// that does not fit in it is refused, and libpng may inflate a compressed ancillary chunk to no
// more than the file's size and a mebibyte (it skips a larger one, with a warning).
void decode_png_with_libpng(const std::string& path, const unsigned char* bytes, std::size_t size,
                            const PngDestination& destination);

}  // namespace mvox
