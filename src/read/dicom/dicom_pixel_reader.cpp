#include "read/dicom/dicom_pixel_reader.h"

#include <gdcmBoxRegion.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmImageRegionReader.h>
#include <gdcmTrace.h>
#include <gdcmUIDs.h>

#include <cstring>
#include <exception>
#include <optional>

#include "error.h"
#include "read/buffer_allocation.h"

namespace mvox {
namespace {

std::string size_text(std::uint32_t columns, std::uint32_t rows) {
  return std::to_string(columns) + "x" + std::to_string(rows);
}

// What GDCM decoded must be what the scan promised, or the bytes would be misread.
void check_image(const gdcm::Image& image, const DicomImageHeader& expected) {
  const unsigned* dims = image.GetDimensions();
  const gdcm::PixelFormat& format = image.GetPixelFormat();
  if (dims[0] != expected.columns || dims[1] != expected.rows)
    throw Error(expected.path, "GDCM decodes a " + size_text(dims[0], dims[1]) +
                                   " image where the header says " +
                                   size_text(expected.columns, expected.rows));
  if (format.GetSamplesPerPixel() != 1 || format.GetBitsAllocated() != expected.bits_allocated ||
      format.GetPixelRepresentation() != (expected.is_signed ? 1 : 0))
    throw Error(expected.path, "GDCM decodes pixels unlike the header's (" +
                                   std::to_string(expected.bits_allocated) + "-bit, " +
                                   (expected.is_signed ? "signed" : "unsigned") + ")");
}

[[noreturn]] void cannot_decode(const DicomImageHeader& h, const std::string& why) {
  throw Error(h.path, "cannot decode its pixel data (transfer syntax " +
                          transfer_syntax_text(h.transfer_syntax_uid) + ")" +
                          (why.empty() ? std::string() : ": " + why));
}

}  // namespace

std::string transfer_syntax_text(const std::string& uid) {
  // The scan only lets UIDs through, but a message must never carry a file's raw bytes.
  std::string safe;
  for (char c : uid) safe += (c >= 32 && c < 127) ? c : '?';
  gdcm::UIDs known;
  if (known.SetFromUID(uid.c_str()) && known.GetName() && *known.GetName())
    return std::string(known.GetName()) + " (" + safe + ")";
  return safe;
}

DicomPixelReader::DicomPixelReader() {
  // GDCM reports problems on std::cerr as it goes; mvox reports them itself, in one line.
  gdcm::Trace::SetDebug(false);
  gdcm::Trace::SetWarning(false);
  gdcm::Trace::SetError(false);
}

void DicomPixelReader::read_frame(const DicomImageHeader& expected, std::uint32_t frame,
                                  std::vector<char>& decoded) {
  // Claimed: the file was DICOM when the series was planned, so anything else now is an error;
  // and it must still be the image that was planned.
  const std::optional<DicomImageHeader> now = read_dicom_image_header(expected.path, true);
  if (!now || now->columns != expected.columns || now->rows != expected.rows ||
      now->frames != expected.frames || now->bits_allocated != expected.bits_allocated ||
      now->is_signed != expected.is_signed ||
      now->transfer_syntax_uid != expected.transfer_syntax_uid)
    throw Error(expected.path, "changed since the series was scanned");
  const std::uint64_t frame_bytes = dicom_frame_bytes(expected);
  resize_buffer(decoded, frame_bytes, expected.path, "a decoded frame");
  try {
    if (expected.frames == 1) {
      gdcm::ImageReader reader;
      reader.SetFileName(expected.path.c_str());
      if (!reader.Read()) cannot_decode(expected, "GDCM cannot read the file");
      const gdcm::Image& image = reader.GetImage();
      check_image(image, expected);
      if (image.GetBufferLength() != frame_bytes)
        cannot_decode(expected, "GDCM decodes " + std::to_string(image.GetBufferLength()) +
                                    " bytes, expected " + std::to_string(frame_bytes));
      if (!image.GetBuffer(decoded.data())) cannot_decode(expected, "");
      return;
    }
    gdcm::ImageRegionReader reader;
    reader.SetFileName(expected.path.c_str());
    if (!reader.ReadInformation()) cannot_decode(expected, "GDCM cannot read the file");
    check_image(reader.GetImage(), expected);
    gdcm::BoxRegion box;
    box.SetDomain(0, expected.columns - 1, 0, expected.rows - 1, frame, frame);
    reader.SetRegion(box);
    if (reader.ComputeBufferLength() != frame_bytes)
      cannot_decode(expected, "GDCM's frame is " + std::to_string(reader.ComputeBufferLength()) +
                                  " bytes, expected " + std::to_string(frame_bytes));
    if (!reader.ReadIntoBuffer(decoded.data(), decoded.size()))
      cannot_decode(expected, "frame " + std::to_string(frame));
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    cannot_decode(expected, e.what());
  }
}

}  // namespace mvox
