#pragma once
// How much data an encoded stream of a given size can decode to, at most, per codec. A header
// that declares more than its stored bytes could ever decode to is lying (or the file is cut
// short), and is refused before anything of the declared size is allocated: a 100-byte file
// must never cost gigabytes.
//
// The bounds are properties of the codecs, not guesses:
// - deflate (zlib, gzip, PNG, TIFF Deflate): the densest code is a length 258 / distance 1 pair
//   in 2 bits (1-bit length and distance codes), so 258 bytes per 2 bits: 1032 to 1;
// - PackBits (TIFF): a 2-byte run codes at most 128 bytes: 64 to 1;
// - LZW (TIFF): a code of at least 9 bits stands for at most 4096 bytes (the table holds 4096
//   entries, each one byte longer than an earlier one): 4096 * 8 / 9, under 3641 to 1;
// - RLE (DICOM): a 2-byte run codes at most 128 bytes: 64 to 1;
// - JPEG lossless: every sample's difference needs a Huffman code of at least 1 bit, and
//   samples have at most 16 bits: 16 to 1;
// - JPEG baseline: every 8x8 block of every component needs at least a DC code and an end of
//   block, 1 bit each, so 64 samples need at least 2 bits: 256 to 1 for 8-bit samples (512 for
//   16-bit), plus the markers and tables, which only make the stream longer.
// Codecs without such a bound (JPEG-LS run mode, JPEG 2000, LZMA, Zstandard, progressive JPEG's
// end-of-band runs) are limited by the memory budget only (memory_plan.h).
#include <cstdint>

namespace mvox {

constexpr std::uint64_t kDeflateMaxRatio = 1032;
constexpr std::uint64_t kPackBitsMaxRatio = 64;
constexpr std::uint64_t kLzwMaxRatio = 3641;
constexpr std::uint64_t kRleMaxRatio = 64;
constexpr std::uint64_t kJpegBaselineMaxRatio = 512;
constexpr std::uint64_t kJpegLosslessMaxRatio = 16;

// Every stream has some fixed overhead (headers, block headers, a final partial code) that is
// not proportional to its length; this allowance covers it for any of the codecs above.
constexpr std::uint64_t kEncodedOverheadBytes = 64 * 1024;

// True when `encoded_bytes` of a codec with `max_ratio` can decode to `decoded_bytes`.
constexpr bool could_decode_to(std::uint64_t encoded_bytes, std::uint64_t max_ratio,
                               std::uint64_t decoded_bytes) {
  // Written without overflow: encoded_bytes * max_ratio can exceed 2^64 for a huge file.
  return decoded_bytes <= kEncodedOverheadBytes ||
         (decoded_bytes - kEncodedOverheadBytes) / max_ratio <= encoded_bytes;
}

}  // namespace mvox
