#pragma once
// The input-format row (read/input_format.h) of image stacks, which takes whatever no other row
// took, without --raw: one grayscale image per slice, decoded by OpenCV (JPEG by libjpeg).
namespace mvox {

struct InputFormat;

// A multi-page TIFF among other images is refused rather than read as its first page.
const InputFormat& image_stack_format();

}  // namespace mvox
