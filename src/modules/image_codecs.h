#pragma once
// OpenCV's image codecs, through the module that links them (image_codecs/image_codecs_api.h),
// loaded on the first call that needs it. For the formats mvox does not decode or encode
// itself: it reads PNG and JPEG slices and writes PNG pictures without OpenCV.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mvox/slice.h"

namespace mvox {

// A decoded image's layout, before its samples are copied.
struct DecodedImageShape {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int channels = 1;
  // The samples' kind in words ("8-bit unsigned", "64-bit float"), and as mvox reads it when it
  // does (u8, u16, i16), with `readable` false otherwise.
  std::string depth_text;
  SampleType type = SampleType::u8;
  bool readable = false;
};

// Where a decoded image goes: the address of width * height * channels samples, rows packed.
// Called once, after decoding; may throw (the exception leaves decode_image_with_opencv).
using DecodedImageDestination = std::function<unsigned char*(const DecodedImageShape& shape)>;

// Loads the module now (if it is not yet) and has OpenCV register its codecs, so that their
// memory counts as the program's when a run's memory is planned. Throws mvox::Error(subject,
// reason) when the module cannot be loaded.
void load_image_codecs(const std::string& subject);

// Decodes the image file `bytes` (`size` bytes), read from `path`, keeping its depth and
// channels, into `destination`. Throws mvox::Error(path, problem) when the module cannot be
// loaded or OpenCV cannot decode the file (the problem gives OpenCV's reason).
void decode_image_with_opencv(const std::string& path, const unsigned char* bytes, std::size_t size,
                              const DecodedImageDestination& destination);

// True when OpenCV can write images named with `extension` (".tif"). Throws mvox::Error(path,
// reason) when the module cannot be loaded.
bool opencv_can_write(const std::string& path, const std::string& extension);

// `slice` (u8 or u16) encoded as the image type `extension` names. Throws mvox::Error(path,
// problem) when the module cannot be loaded or OpenCV cannot encode it.
std::vector<unsigned char> encode_image_with_opencv(const std::string& path,
                                                    const std::string& extension,
                                                    const SliceView& slice);

}  // namespace mvox
