// The DICOM module: GDCM's pixel decoders behind dicom_codecs_api.h. Built as
// libmvox_dicom_codecs.so and loaded only by runs that read a DICOM series.
#include <gdcmBoxRegion.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmImageRegionReader.h>
#include <gdcmTrace.h>
#include <gdcmUIDs.h>

#include <cstdio>
#include <exception>
#include <string>

#include "modules/dicom_codecs/dicom_codecs_api.h"

namespace {

// A problem that ends the decoding, in the words the API promises.
struct Problem {
  std::string text;
  int status = -1;  // -2: GDCM's image is not the header's
};

std::string size_text(std::uint32_t columns, std::uint32_t rows) {
  return std::to_string(columns) + "x" + std::to_string(rows);
}

// What GDCM decoded must be what the scan promised, or the bytes would be misread.
void check_image(const gdcm::Image& image, const mvox_dicom_frame& expected) {
  const unsigned* dims = image.GetDimensions();
  const gdcm::PixelFormat& format = image.GetPixelFormat();
  if (dims[0] != expected.columns || dims[1] != expected.rows)
    throw Problem{"GDCM decodes a " + size_text(dims[0], dims[1]) +
                      " image where the header says " + size_text(expected.columns, expected.rows),
                  -2};
  if (format.GetSamplesPerPixel() != 1 || format.GetBitsAllocated() != expected.bits_allocated ||
      format.GetPixelRepresentation() != (expected.is_signed ? 1 : 0))
    throw Problem{"GDCM decodes pixels unlike the header's (" +
                      std::to_string(expected.bits_allocated) + "-bit, " +
                      (expected.is_signed ? "signed" : "unsigned") + ")",
                  -2};
}

void decode(const mvox_dicom_frame& expected, unsigned char* destination, size_t bytes) {
  if (expected.frames == 1) {
    gdcm::ImageReader reader;
    reader.SetFileName(expected.path);
    if (!reader.Read()) throw Problem{"GDCM cannot read the file"};
    const gdcm::Image& image = reader.GetImage();
    check_image(image, expected);
    if (image.GetBufferLength() != bytes)
      throw Problem{"GDCM decodes " + std::to_string(image.GetBufferLength()) +
                        " bytes where the header says " + std::to_string(bytes),
                    -2};
    if (!image.GetBuffer(reinterpret_cast<char*>(destination))) throw Problem{""};
    return;
  }
  gdcm::ImageRegionReader reader;
  reader.SetFileName(expected.path);
  if (!reader.ReadInformation()) throw Problem{"GDCM cannot read the file"};
  check_image(reader.GetImage(), expected);
  gdcm::BoxRegion box;
  box.SetDomain(0, expected.columns - 1, 0, expected.rows - 1, expected.frame, expected.frame);
  reader.SetRegion(box);
  if (reader.ComputeBufferLength() != bytes)
    throw Problem{"GDCM's frame is " + std::to_string(reader.ComputeBufferLength()) +
                      " bytes where the header says " + std::to_string(bytes),
                  -2};
  if (!reader.ReadIntoBuffer(reinterpret_cast<char*>(destination), bytes))
    throw Problem{"frame " + std::to_string(expected.frame)};
}

void set_text(char* out, size_t out_bytes, const std::string& text) {
  if (out != nullptr && out_bytes > 0) std::snprintf(out, out_bytes, "%s", text.c_str());
}

}  // namespace

extern "C" {

int mvox_dicom_codecs_api_version(void) { return MVOX_DICOM_CODECS_API_VERSION; }

int mvox_dicom_decode_frame(const mvox_dicom_frame* frame, unsigned char* destination,
                            size_t destination_bytes, char* error, size_t error_bytes) {
  // GDCM reports problems on std::cerr as it goes; mvox reports them itself, in one line.
  gdcm::Trace::SetDebug(false);
  gdcm::Trace::SetWarning(false);
  gdcm::Trace::SetError(false);
  try {
    decode(*frame, destination, destination_bytes);
    return 0;
  } catch (const Problem& problem) {
    set_text(error, error_bytes, problem.text);
    return problem.status;
  } catch (const std::exception& e) {
    set_text(error, error_bytes, e.what());
  } catch (...) {
    set_text(error, error_bytes, "GDCM failed");
  }
  return -1;
}

void mvox_dicom_transfer_syntax_name(const char* uid, char* name, size_t name_bytes) {
  set_text(name, name_bytes, "");
  try {
    gdcm::UIDs known;
    if (known.SetFromUID(uid) && known.GetName() && *known.GetName())
      set_text(name, name_bytes, known.GetName());
  } catch (...) {
    // Unknown: the caller shows the bare UID.
  }
}

}  // extern "C"
