#pragma once
// Test support: small DICOM files written with GDCM (independently of mvox's reader), with
// exactly the attributes a test sets, and re-encoded copies in other transfer syntaxes.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace mvox::test {

constexpr const char* kExplicitLittleEndianUid = "1.2.840.10008.1.2.1";
constexpr const char* kImplicitLittleEndianUid = "1.2.840.10008.1.2";
constexpr const char* kExplicitBigEndianUid = "1.2.840.10008.1.2.2";
constexpr const char* kRleLosslessUid = "1.2.840.10008.1.2.5";
constexpr const char* kJpegLosslessUid = "1.2.840.10008.1.2.4.70";  // process 14, SV1
constexpr const char* kJpegLsLosslessUid = "1.2.840.10008.1.2.4.80";
constexpr const char* kJpeg2000LosslessUid = "1.2.840.10008.1.2.4.90";

struct DicomSliceSpec {
  std::uint32_t width = 16;   // Columns
  std::uint32_t height = 12;  // Rows
  std::uint32_t frames = 1;   // NumberOfFrames is written when > 1
  std::uint16_t bits_allocated = 16;
  std::uint16_t bits_stored = 16;
  bool is_signed = false;
  // Stored values, width * height * frames, x fastest; written as bits_allocated-wide samples
  // (values outside bits_stored keep their high bits: old files do that).
  std::vector<std::int64_t> stored;
  std::string series_uid = "1.2.826.0.1.3680043.10.543.1";
  std::string series_description;
  std::string modality = "CT";  // (0008,0060)
  std::optional<std::int64_t> instance_number;
  std::optional<std::array<double, 3>> position;       // ImagePositionPatient
  std::optional<std::array<double, 6>> orientation;    // ImageOrientationPatient
  std::optional<std::array<double, 2>> pixel_spacing;  // row spacing, column spacing
  std::optional<double> spacing_between_slices;
  std::optional<double> slope, intercept;  // RescaleSlope, RescaleIntercept
  std::string photometric = "MONOCHROME2";
  std::uint16_t samples_per_pixel = 1;
  bool with_image = true;  // false: no Rows, Columns, pixel attributes or Pixel Data
  std::string sop_class_uid = "1.2.840.10008.5.1.4.1.1.2";  // CT Image Storage
  // Native transfer syntax of the file: explicit or implicit VR little endian, or explicit VR
  // big endian. Compressed files come from recode().
  std::string transfer_syntax_uid = kExplicitLittleEndianUid;
  bool with_meta = true;  // false: a bare data set, no preamble or file meta group
};

// Writes `spec` to `path` with gdcm::Writer. Fails the current test (ADD_FAILURE) when GDCM
// cannot write it.
void write_dicom(const std::string& path, const DicomSliceSpec& spec);

// Reads `in` with gdcm::ImageReader and writes it to `out` in `transfer_syntax_uid` (lossless
// compressions, or the native ones) with gdcm::ImageChangeTransferSyntax. Returns false (and
// records a failure) when GDCM cannot.
bool recode(const std::string& in, const std::string& out, const std::string& transfer_syntax_uid);

// Writes `depth` slices of 8-bit `samples` (width x height each, x fastest, then y, then slice)
// into `directory` as one axial series, slice z at z mm and named s1000+z.dcm, each recoded
// into the transfer syntax `syntax_of(z)`: a series whose slices mix compressions.
void write_dicom_series(const std::string& directory, const std::string& samples,
                        std::uint32_t width, std::uint32_t height, std::uint32_t depth,
                        const std::function<std::string(std::uint32_t)>& syntax_of);

// A unit vector pair for ImageOrientationPatient, rotated off the axes by the given angles
// (degrees) about x, then y, then z: an oblique plane.
std::array<double, 6> oblique_orientation(double about_x_deg, double about_y_deg,
                                          double about_z_deg);

}  // namespace mvox::test
