#pragma once
// Walks a DICOM file element by element, reading only element headers and the few top-level
// values mvox needs, never the pixel data. It serves two purposes:
// - header scanning: a series of thousands of files is planned from these values alone;
// - safety: Debian's GDCM is built with assertions, and a file truncated inside an element header
//   makes it abort the process. GDCM only ever gets files this walk found well-formed.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace mvox {

// A tag as one number, group in the high 16 bits: dicom_tag(0x0028, 0x0010) is Rows.
constexpr std::uint32_t dicom_tag(std::uint16_t group, std::uint16_t element) {
  return (std::uint32_t{group} << 16) | element;
}

// "(0028,0010)", for messages.
std::string dicom_tag_text(std::uint32_t tag);

// One fragment of encapsulated (compressed) pixel data, as far as the checks before decoding
// need it (dicom_codestream.h): its length, first bytes and last bytes.
struct DicomFragment {
  std::uint64_t length = 0;
  std::string head;  // the first min(length, kDicomFragmentHeadBytes) bytes
  std::string tail;  // the last min(length, kDicomFragmentTailBytes) bytes
};
constexpr std::size_t kDicomFragmentHeadBytes = 2048;  // room for the JPEG tables before SOF
constexpr std::size_t kDicomFragmentTailBytes = 16;

struct DicomFileScan {
  // (0002,0010); without a file meta group, the encoding the walk found (implicit or explicit
  // VR little endian).
  std::string transfer_syntax_uid;
  std::string media_storage_sop_class_uid;  // (0002,0002); empty without a meta group
  bool big_endian = false;     // values in `values` are big-endian (explicit VR big endian)
  std::uint32_t last_tag = 0;  // of the top-level data set's last element
  bool has_pixel_data = false;
  bool pixel_data_encapsulated = false;  // compressed: fragments instead of one value
  std::uint64_t pixel_data_bytes = 0;    // native pixel data: its value length
  // Encapsulated pixel data: the fragments after the basic offset table (the first item).
  std::vector<DicomFragment> fragments;
  // Raw value bytes of the top-level elements whose tags were asked for and are present, in the
  // file's byte order (text values keep their padding).
  std::map<std::uint32_t, std::string> values;
};

// True when `path` has the DICOM preamble: the four bytes "DICM" at offset 128.
bool has_dicom_preamble(const std::string& path);

// True when `path` ends in .dcm or .dicom (case-insensitive).
bool has_dicom_extension(const std::string& path);

// Walks every element of the file at `path` (including those after the pixel data, which GDCM
// reads too) and keeps the values of the top-level elements in `wanted` (sorted ascending).
// A file is DICOM when it has the preamble, or `claimed` (the caller knows it is meant to be
// DICOM, e.g. by its extension), or when it has neither but its first bytes are a plausible
// data element of group 0x0000, 0x0002 or 0x0008 (old files without a preamble).
// Returns std::nullopt for a file that is not DICOM, or that has neither preamble nor claim and
// does not walk cleanly. Throws mvox::Error(path, problem) for a DICOM file that is truncated or
// malformed (problem names the element and byte offset), or whose data set is deflated
// (1.2.840.10008.1.2.1.99, not supported).
// The transfer syntax UID must be a UID (digits and dots), or the file is malformed.
// Memory: a few kilobytes beyond the kept values and fragment ends; nesting is limited to 32
// levels.
std::optional<DicomFileScan> scan_dicom_file(const std::string& path, const std::uint32_t* wanted,
                                             std::size_t wanted_count, bool claimed);

}  // namespace mvox
