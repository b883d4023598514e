// Fuzzes the slice image header reader (src/read/image_stack/image_header.h), which decides from a
// PNG, JPEG, BMP or PNM header alone what a stack holds and how much memory decoding it will take,
// before any decoder sees the file. Properties: it never reads outside the bytes
// (AddressSanitizer), a header it returns has a size, one or three channels and an 8- or 16-bit
// type, and a PNG it passes (image_size_problem) has compressed data that can hold its image.
#include <cstddef>
#include <cstdint>
#include <optional>

#include "fuzz_check.h"
#include "read/compression_bounds.h"
#include "read/image_stack/image_header.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::optional<mvox::ImageHeader> header = mvox::parse_image_header(data, size);
  if (!header) return 0;
  MVOX_FUZZ_CHECK(header->width > 0 && header->height > 0, "empty image");
  MVOX_FUZZ_CHECK(header->channels == 1 || header->channels == 3, std::to_string(header->channels));
  MVOX_FUZZ_CHECK(header->type == mvox::SampleType::u8 || header->type == mvox::SampleType::u16,
                  "sample type");
  MVOX_FUZZ_CHECK(header->encoded_bytes <= size, "more IDAT bytes than the file");
  if (mvox::image_size_problem(*header).empty()) {
    MVOX_FUZZ_CHECK(std::uint64_t{header->width} * header->height <= mvox::kMaxDecodedImagePixels,
                    "too many pixels passed");
    if (header->format == mvox::ImageFormat::png)
      MVOX_FUZZ_CHECK(mvox::could_decode_to(header->encoded_bytes, mvox::kDeflateMaxRatio,
                                            header->stream_bytes),
                      "a PNG too short for its image passed");
  }
  return 0;
}
