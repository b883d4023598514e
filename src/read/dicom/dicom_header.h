#pragma once
// What mvox needs to know about one DICOM image file before reading its pixels: identity,
// geometry, pixel layout and rescale, from a header-only scan (dicom_file_scan.h).
#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace mvox {

struct DicomImageHeader {
  std::string path;
  std::string transfer_syntax_uid;
  std::string series_uid;                       // (0020,000E); empty when the file has none
  std::string series_description;               // (0008,103E), printable ASCII only, for messages
  std::string modality;                         // (0008,0060): "CT" means Hounsfield units
  std::optional<std::int64_t> instance_number;  // (0020,0013)

  std::uint32_t columns = 0;  // (0028,0011): samples per row, x
  std::uint32_t rows = 0;     // (0028,0010): rows, y
  std::uint32_t frames = 1;   // (0028,0008) NumberOfFrames
  std::uint16_t samples_per_pixel = 1;
  std::string photometric = "MONOCHROME2";
  std::uint16_t bits_allocated = 0;  // 8, 16 or 32
  std::uint16_t bits_stored = 0;     // 1 .. bits_allocated
  bool is_signed = false;            // PixelRepresentation 1: two's complement

  // (0020,0032): patient position of the first transmitted pixel, mm (LPS).
  std::optional<std::array<double, 3>> position;
  // (0020,0037): row cosine (direction of increasing column, x), then column cosine
  // (direction of increasing row, y); unit vectors as written in the file.
  std::optional<std::array<double, 6>> orientation;
  // (0028,0030) as in the file: row spacing (between rows, y) first, then column spacing (x).
  std::optional<std::array<double, 2>> pixel_spacing;
  // The PixelSpacing text when it is present but not two positive numbers (then pixel_spacing is
  // empty): old files have such values, and spacing alone should not make a file unreadable.
  std::string unusable_pixel_spacing;
  std::optional<double> spacing_between_slices;  // (0018,0088)
  std::optional<double> slice_thickness;         // (0018,0050)
  double rescale_slope = 1;                      // (0028,1053)
  double rescale_intercept = 0;                  // (0028,1052)
};

// Reads the header of `path` (header only: the pixel data are skipped) when it is a DICOM
// image. `claimed`: the caller expects DICOM (a .dcm name), so a malformed file is an error
// rather than "not DICOM" (see scan_dicom_file).
// Returns std::nullopt for a file that is not DICOM, or DICOM without an image (a DICOMDIR,
// a report: no Rows, Columns or Pixel Data, and a data set that goes on past group 0028).
// Throws mvox::Error(path, problem) for a truncated or malformed file (also one cut cleanly
// between two elements: a data set that stops before group 0028 without an image); a colour image
// (only grayscale, MONOCHROME1 or MONOCHROME2 with one sample per pixel, is read); an unsupported
// pixel layout (BitsAllocated other than 8, 16 or 32, HighBit other than BitsStored - 1);
// native pixel data shorter than Rows x Columns x frames samples; compressed pixel data whose
// codestreams disagree with the header (compressed_pixel_data_problem); values that are not numbers
// where numbers belong (positions, spacings, rescale), or a zero rescale slope.
std::optional<DicomImageHeader> read_dicom_image_header(const std::string& path, bool claimed);

// Bytes of native pixel data one frame needs: rows * columns * bits_allocated / 8.
std::uint64_t dicom_frame_bytes(const DicomImageHeader& header);

}  // namespace mvox
