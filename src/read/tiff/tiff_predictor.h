#pragma once
// What libtiff does to a strip or tile after its codec has decompressed it, for pages of one
// sample per pixel: puts 16- and 32-bit samples in the machine's byte order, and undoes the
// horizontal differencing predictor (TIFF's Predictor 2). mvox inflates deflate data itself
// (to check them whole, zlib_stream_check.h) and finishes them with this, rather than have
// libtiff inflate them a second time.
#include <cstddef>
#include <cstdint>

namespace mvox {

// Finishes `rows` rows of `row_samples` samples of `sample_bytes` bytes (1, 2 or 4) at
// `samples`, rows packed, in place: bytes swapped when `byte_swapped` (the file's byte order
// is not the machine's), then `predictor` undone row by row with wrap-around integer sums, as
// libtiff does even for 32-bit float samples. Returns false, leaving the samples as they were,
// for a predictor other than 1 (none) and 2 (horizontal), such as 3 (floating point).
bool finish_tiff_samples(unsigned char* samples, std::size_t rows, std::size_t row_samples,
                         std::size_t sample_bytes, bool byte_swapped, std::uint16_t predictor);

// Reverses the order of the bits in each of `count` bytes, in place: what libtiff does to the
// stored bytes of a page whose FillOrder is 2 (least significant bit first) before decoding.
void reverse_bit_order(unsigned char* bytes, std::size_t count);

}  // namespace mvox
