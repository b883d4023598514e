#pragma once
// The input-format row (read/input_format.h) of TIFF stacks.
namespace mvox {

struct InputFormat;

// Claims the input, without --raw, when every listed file is a .tif or .tiff: one multi-page
// TIFF, several, or a folder of single-page slices, all read page by page by TiffStackSource.
// TIFF files mixed with other images stay with the image-stack row.
const InputFormat& tiff_stack_format();

}  // namespace mvox
