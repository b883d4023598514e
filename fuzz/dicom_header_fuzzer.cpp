// Fuzzes mvox's own DICOM element walk and header checks (src/read/dicom/dicom_file_scan.h,
// src/read/dicom/dicom_header.h, src/read/dicom/dicom_codestream.h): the code that decides whether
// a file is safe to hand to GDCM, whose Debian build aborts or corrupts memory on malformed files.
// GDCM itself is not called here.
//
// Input: one flag byte (bit 0: the caller claims the file is DICOM, as a .dcm name does), then
// the file's bytes. Properties: a refusal is one printable line naming the file; an accepted
// header describes a grayscale image of positive size whose native pixel data the file holds.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "error.h"
#include "fuzz_check.h"
#include "memory_file.h"
#include "read/dicom/dicom_header.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool claimed = (data[0] & 1) != 0;
  const std::string& path = mvox::fuzz::memory_file_with(data + 1, size - 1);
  try {
    const std::optional<mvox::DicomImageHeader> header =
        mvox::read_dicom_image_header(path, claimed);
    if (header) {
      MVOX_FUZZ_CHECK(header->rows > 0 && header->columns > 0, "an image without pixels");
      MVOX_FUZZ_CHECK(mvox::dicom_frame_bytes(*header) > 0, "frames of no bytes");
    }
  } catch (const mvox::Error& error) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(error.what()), error.what());
    MVOX_FUZZ_CHECK(error.subject() == path, error.what());
  }
  return 0;
}
