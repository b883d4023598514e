#include "read/dicom/dicom_header.h"

#include <cmath>
#include <cstdlib>
#include <vector>

#include "error.h"
#include "read/dicom/dicom_codestream.h"
#include "read/dicom/dicom_file_scan.h"

namespace mvox {
namespace {

constexpr std::uint32_t kModality = dicom_tag(0x0008, 0x0060);
constexpr std::uint32_t kSeriesDescription = dicom_tag(0x0008, 0x103E);
constexpr std::uint32_t kSliceThickness = dicom_tag(0x0018, 0x0050);
constexpr std::uint32_t kSpacingBetweenSlices = dicom_tag(0x0018, 0x0088);
constexpr std::uint32_t kSeriesInstanceUid = dicom_tag(0x0020, 0x000E);
constexpr std::uint32_t kInstanceNumber = dicom_tag(0x0020, 0x0013);
constexpr std::uint32_t kImagePositionPatient = dicom_tag(0x0020, 0x0032);
constexpr std::uint32_t kImageOrientationPatient = dicom_tag(0x0020, 0x0037);
constexpr std::uint32_t kSamplesPerPixel = dicom_tag(0x0028, 0x0002);
constexpr std::uint32_t kPhotometricInterpretation = dicom_tag(0x0028, 0x0004);
constexpr std::uint32_t kNumberOfFrames = dicom_tag(0x0028, 0x0008);
constexpr std::uint32_t kRows = dicom_tag(0x0028, 0x0010);
constexpr std::uint32_t kColumns = dicom_tag(0x0028, 0x0011);
constexpr std::uint32_t kPixelSpacing = dicom_tag(0x0028, 0x0030);
constexpr std::uint32_t kBitsAllocated = dicom_tag(0x0028, 0x0100);
constexpr std::uint32_t kBitsStored = dicom_tag(0x0028, 0x0101);
constexpr std::uint32_t kHighBit = dicom_tag(0x0028, 0x0102);
constexpr std::uint32_t kPixelRepresentation = dicom_tag(0x0028, 0x0103);
constexpr std::uint32_t kRescaleIntercept = dicom_tag(0x0028, 0x1052);
constexpr std::uint32_t kRescaleSlope = dicom_tag(0x0028, 0x1053);

constexpr const char* kMediaStorageDirectory = "1.2.840.10008.1.3.10";  // DICOMDIR

// Sorted ascending, as scan_dicom_file needs.
constexpr std::uint32_t kWantedTags[] = {kModality,
                                         kSeriesDescription,
                                         kSliceThickness,
                                         kSpacingBetweenSlices,
                                         kSeriesInstanceUid,
                                         kInstanceNumber,
                                         kImagePositionPatient,
                                         kImageOrientationPatient,
                                         kSamplesPerPixel,
                                         kPhotometricInterpretation,
                                         kNumberOfFrames,
                                         kRows,
                                         kColumns,
                                         kPixelSpacing,
                                         kBitsAllocated,
                                         kBitsStored,
                                         kHighBit,
                                         kPixelRepresentation,
                                         kRescaleIntercept,
                                         kRescaleSlope};

constexpr bool strictly_ascending(const std::uint32_t* tags, std::size_t count) {
  for (std::size_t i = 1; i < count; ++i)
    if (tags[i - 1] >= tags[i]) return false;
  return true;
}
static_assert(strictly_ascending(kWantedTags, std::size(kWantedTags)),
              "scan_dicom_file binary-searches the wanted tags");

// Reads the values of one file's scan, naming the file and the element in every error.
class HeaderValues {
 public:
  HeaderValues(const std::string& path, const DicomFileScan& scan) : path_(path), scan_(scan) {}

  bool has(std::uint32_t tag) const { return scan_.values.count(tag) != 0; }

  // A text value without its padding (trailing spaces and NULs, leading spaces).
  std::string text(std::uint32_t tag) const {
    auto found = scan_.values.find(tag);
    if (found == scan_.values.end()) return {};
    std::string value = found->second;
    while (!value.empty() && (value.back() == ' ' || value.back() == '\0')) value.pop_back();
    const std::size_t first = value.find_first_not_of(' ');
    return first == std::string::npos ? std::string() : value.substr(first);
  }

  // An unsigned short (US); `fallback` when absent.
  std::uint16_t us(std::uint32_t tag, const char* name, std::uint16_t fallback) const {
    auto found = scan_.values.find(tag);
    if (found == scan_.values.end()) return fallback;
    const std::string& bytes = found->second;
    // Implicit VR files may hold an empty value; a non-empty one must be one 16-bit number.
    if (bytes.empty()) return fallback;
    if (bytes.size() != 2) fail(tag, name, "is " + std::to_string(bytes.size()) + " bytes long");
    const auto b0 = static_cast<unsigned char>(bytes[0]);
    const auto b1 = static_cast<unsigned char>(bytes[1]);
    return static_cast<std::uint16_t>(scan_.big_endian ? b0 << 8 | b1 : b1 << 8 | b0);
  }

  // Decimal strings (DS) or integer strings (IS) separated by backslashes; nullopt when the
  // element is absent or empty, an error when a value is not a finite number.
  std::optional<std::vector<double>> numbers(std::uint32_t tag, const char* name) const {
    const std::string value = text(tag);
    if (value.empty()) return std::nullopt;
    std::vector<double> result;
    std::size_t start = 0;
    for (;;) {
      const std::size_t end = value.find('\\', start);
      std::string part = value.substr(start, end == std::string::npos ? end : end - start);
      const std::size_t first = part.find_first_not_of(' ');
      const std::size_t last = part.find_last_not_of(' ');
      part = first == std::string::npos ? std::string() : part.substr(first, last - first + 1);
      char* parsed_end = nullptr;
      const double number = std::strtod(part.c_str(), &parsed_end);
      if (part.empty() || *parsed_end != '\0' || !std::isfinite(number))
        fail(tag, name, "'" + printable(value) + "' is not a list of numbers");
      result.push_back(number);
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return result;
  }

  // Exactly `count` numbers, or nullopt when absent.
  template <std::size_t count>
  std::optional<std::array<double, count>> fixed(std::uint32_t tag, const char* name) const {
    const auto values = numbers(tag, name);
    if (!values) return std::nullopt;
    if (values->size() != count)
      fail(tag, name,
           "'" + printable(text(tag)) + "' has " + std::to_string(values->size()) +
               " values, expected " + std::to_string(count));
    std::array<double, count> result;
    for (std::size_t i = 0; i < count; ++i) result[i] = (*values)[i];
    return result;
  }

  std::optional<double> single(std::uint32_t tag, const char* name) const {
    const auto value = fixed<1>(tag, name);
    if (!value) return std::nullopt;
    return (*value)[0];
  }

  // One positive number, or nullopt when absent or anything else.
  std::optional<double> positive_or_nothing(std::uint32_t tag) const {
    try {
      const auto value = single(tag, "");
      if (value && *value > 0) return value;
    } catch (const Error&) {
    }
    return std::nullopt;
  }

  [[noreturn]] void fail(std::uint32_t tag, const char* name, const std::string& problem) const {
    throw Error(path_, std::string(name) + " " + dicom_tag_text(tag) + " " + problem);
  }

  // Text made safe for a one-line message: printable ASCII, at most 64 characters.
  static std::string printable(const std::string& text) {
    std::string result;
    for (char c : text) {
      if (result.size() == 64) return result + "...";
      result += (c >= 32 && c < 127) ? c : '?';
    }
    return result;
  }

 private:
  const std::string& path_;
  const DicomFileScan& scan_;
};

bool is_grayscale(const std::string& photometric) {
  return photometric == "MONOCHROME1" || photometric == "MONOCHROME2";
}

}  // namespace

std::uint64_t dicom_frame_bytes(const DicomImageHeader& header) {
  return std::uint64_t{header.rows} * header.columns * (header.bits_allocated / 8u);
}

std::optional<DicomImageHeader> read_dicom_image_header(const std::string& path, bool claimed) {
  const std::optional<DicomFileScan> scan =
      scan_dicom_file(path, kWantedTags, std::size(kWantedTags), claimed);
  if (!scan) return std::nullopt;
  const HeaderValues values(path, *scan);
  if (!values.has(kRows) || !values.has(kColumns)) {
    // DICOM objects without an image (DICOMDIR, reports, presentation states) are not slices.
    // Elements come in ascending tag order, so one whose data set stops before the Image Pixel
    // module's group (0028) without being a directory has more likely lost its end.
    const bool directory = scan->media_storage_sop_class_uid == kMediaStorageDirectory;
    if (!scan->has_pixel_data && (directory || (scan->last_tag >> 16) > 0x0028))
      return std::nullopt;
    throw Error(path, "DICOM file without Rows and Columns whose data set stops at " +
                          dicom_tag_text(scan->last_tag) + ": truncated, or not an image");
  }

  DicomImageHeader h;
  h.path = path;
  h.transfer_syntax_uid = scan->transfer_syntax_uid;
  h.series_uid = values.text(kSeriesInstanceUid);
  h.series_description = HeaderValues::printable(values.text(kSeriesDescription));
  h.modality = HeaderValues::printable(values.text(kModality));
  while (!h.modality.empty() && h.modality.back() == ' ') h.modality.pop_back();  // CS padding
  h.rows = values.us(kRows, "Rows", 0);
  h.columns = values.us(kColumns, "Columns", 0);
  if (h.rows == 0 || h.columns == 0)
    throw Error(path, "image is " + std::to_string(h.columns) + "x" + std::to_string(h.rows) +
                          " (Columns x Rows): no pixels");
  if (!scan->has_pixel_data)
    throw Error(path,
                "has Rows and Columns but no Pixel Data (7FE0,0010): truncated, or "
                "not an image mvox can read");

  h.samples_per_pixel = values.us(kSamplesPerPixel, "SamplesPerPixel", 1);
  if (values.has(kPhotometricInterpretation))
    h.photometric = HeaderValues::printable(values.text(kPhotometricInterpretation));
  if (h.samples_per_pixel != 1 || !is_grayscale(h.photometric))
    throw Error(path, "colour image (PhotometricInterpretation " + h.photometric + ", " +
                          std::to_string(h.samples_per_pixel) +
                          " samples per pixel): mvox reads grayscale (MONOCHROME1 or "
                          "MONOCHROME2) DICOM only");

  h.bits_allocated = values.us(kBitsAllocated, "BitsAllocated", 0);
  if (h.bits_allocated != 8 && h.bits_allocated != 16 && h.bits_allocated != 32)
    throw Error(
        path, "BitsAllocated is " + std::to_string(h.bits_allocated) + ", mvox reads 8, 16 or 32");
  h.bits_stored = values.us(kBitsStored, "BitsStored", h.bits_allocated);
  if (h.bits_stored == 0 || h.bits_stored > h.bits_allocated)
    throw Error(path, "BitsStored is " + std::to_string(h.bits_stored) + " with BitsAllocated " +
                          std::to_string(h.bits_allocated));
  const std::uint16_t high_bit = values.us(kHighBit, "HighBit", h.bits_stored - 1);
  // Stored bits not at the bottom of the sample are retired usage; GDCM's masking assumes this.
  if (high_bit != h.bits_stored - 1)
    throw Error(path, "HighBit is " + std::to_string(high_bit) + " with BitsStored " +
                          std::to_string(h.bits_stored) + ", mvox reads HighBit = BitsStored - 1");
  const std::uint16_t representation = values.us(kPixelRepresentation, "PixelRepresentation", 0);
  if (representation > 1)
    throw Error(path, "PixelRepresentation is " + std::to_string(representation) +
                          ", expected 0 (unsigned) or 1 (signed)");
  h.is_signed = representation == 1;

  if (const auto frames = values.single(kNumberOfFrames, "NumberOfFrames")) {
    if (*frames < 1 || *frames > 1e9 || std::floor(*frames) != *frames)
      values.fail(kNumberOfFrames, "NumberOfFrames", "is not a positive integer");
    h.frames = static_cast<std::uint32_t>(*frames);
  }
  if (!scan->pixel_data_encapsulated && scan->pixel_data_bytes < dicom_frame_bytes(h) * h.frames) {
    throw Error(path, "pixel data holds " + std::to_string(scan->pixel_data_bytes) + " bytes, " +
                          std::to_string(h.columns) + "x" + std::to_string(h.rows) +
                          (h.frames > 1 ? "x" + std::to_string(h.frames) : std::string()) +
                          " samples of " + std::to_string(h.bits_allocated) + " bits need " +
                          std::to_string(dicom_frame_bytes(h) * h.frames));
  }

  if (scan->pixel_data_encapsulated) {
    const std::string problem = compressed_pixel_data_problem(scan->fragments, h);
    if (!problem.empty()) throw Error(path, problem);
  }

  if (const auto number = values.single(kInstanceNumber, "InstanceNumber")) {
    if (std::floor(*number) != *number || std::fabs(*number) > 1e15)
      values.fail(kInstanceNumber, "InstanceNumber", "is not an integer");
    h.instance_number = static_cast<std::int64_t>(*number);
  }
  h.position = values.fixed<3>(kImagePositionPatient, "ImagePositionPatient");
  h.orientation = values.fixed<6>(kImageOrientationPatient, "ImageOrientationPatient");

  // Old files carry odd PixelSpacing values; those leave the spacing unknown instead of failing.
  const std::string spacing_text = values.text(kPixelSpacing);
  if (!spacing_text.empty()) {
    try {
      h.pixel_spacing = values.fixed<2>(kPixelSpacing, "PixelSpacing");
    } catch (const Error&) {
      h.pixel_spacing.reset();
    }
    if (h.pixel_spacing && ((*h.pixel_spacing)[0] <= 0 || (*h.pixel_spacing)[1] <= 0))
      h.pixel_spacing.reset();
    if (!h.pixel_spacing) h.unusable_pixel_spacing = HeaderValues::printable(spacing_text);
  }
  // Only fallbacks for the slice spacing (positions come first), so a bad one is ignored.
  h.spacing_between_slices = values.positive_or_nothing(kSpacingBetweenSlices);
  h.slice_thickness = values.positive_or_nothing(kSliceThickness);

  if (const auto slope = values.single(kRescaleSlope, "RescaleSlope")) {
    if (*slope == 0) values.fail(kRescaleSlope, "RescaleSlope", "is 0");
    h.rescale_slope = *slope;
  }
  if (const auto intercept = values.single(kRescaleIntercept, "RescaleIntercept"))
    h.rescale_intercept = *intercept;
  return h;
}

}  // namespace mvox
