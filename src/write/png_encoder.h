#pragma once
// Encodes grey pictures and slices as PNG with libpng directly, so that writing a picture
// (`--image`, `demo`, `render`, `phantom`'s slices) never loads OpenCV.
//
// The bytes are those OpenCV's cv::imencode(".png") writes for the same image, so pictures are
// unchanged by the move (tests/host/png_encoder_test.cpp compares them): the same libpng and
// zlib with OpenCV's default settings, the SUB row filter, zlib level 1 (Z_BEST_SPEED) and the
// Z_RLE strategy, fast settings that suit pictures with large flat areas.
#include <vector>

#include "mvox/slice.h"

namespace mvox {

// `slice` (u8 or u16, any row stride) as a PNG file's bytes. Throws mvox::Error("PNG", reason)
// when libpng fails (only when memory runs out).
std::vector<unsigned char> encode_png(const SliceView& slice);

}  // namespace mvox
