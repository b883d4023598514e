#include "read/dicom/dicom_pixel_reader.h"

#include <optional>

#include "error.h"
#include "modules/dicom_codecs/dicom_codecs_api.h"
#include "modules/module_loader.h"
#include "read/buffer_allocation.h"

namespace mvox {
namespace {

constexpr ModuleName kDicomCodecs{
    "libmvox_dicom_codecs.so", "DICOM module (GDCM)",
    "GDCM (apt-get install libgdcm-dev; scripts/install_deps.sh installs it)"};

struct Api {
  decltype(&mvox_dicom_decode_frame) decode = nullptr;
  decltype(&mvox_dicom_transfer_syntax_name) syntax_name = nullptr;
};

// The module's functions, loaded at the first use; or mvox::Error(subject, why not).
const Api& api(const std::string& subject) {
  return module_functions<Api>(kDicomCodecs, "mvox_dicom_codecs_api_version",
                               MVOX_DICOM_CODECS_API_VERSION, subject,
                               [&](void* handle, Api& functions) {
                                 resolve_function(handle, "mvox_dicom_decode_frame",
                                                  &functions.decode, kDicomCodecs, subject);
                                 resolve_function(handle, "mvox_dicom_transfer_syntax_name",
                                                  &functions.syntax_name, kDicomCodecs, subject);
                               });
}

}  // namespace

std::string transfer_syntax_text(const std::string& uid) {
  // The scan only lets UIDs through, but a message must never carry a file's raw bytes.
  std::string safe;
  for (char c : uid) safe += (c >= 32 && c < 127) ? c : '?';
  char name[256] = "";
  api(safe).syntax_name(uid.c_str(), name, sizeof name);
  return name[0] != '\0' ? std::string(name) + " (" + safe + ")" : safe;
}

void DicomPixelReader::load(const std::string& subject) const { api(subject); }

void DicomPixelReader::read_frame(const DicomImageHeader& expected, std::uint32_t frame,
                                  std::vector<char>& decoded) {
  const Api& functions = api(expected.path);
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
  const mvox_dicom_frame request{expected.path.c_str(),     frame,         expected.frames,
                                 expected.columns,          expected.rows, expected.bits_allocated,
                                 expected.is_signed ? 1 : 0};
  char problem[1024] = "";
  const int status = functions.decode(&request, reinterpret_cast<unsigned char*>(decoded.data()),
                                      decoded.size(), problem, sizeof problem);
  if (status == 0) return;
  if (status == -2) throw Error(expected.path, problem);
  throw Error(expected.path,
              "cannot decode its pixel data (transfer syntax " +
                  transfer_syntax_text(expected.transfer_syntax_uid) + ")" +
                  (problem[0] == '\0' ? std::string() : ": " + std::string(problem)));
}

}  // namespace mvox
