#include "read/nifti/nifti_file.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "error.h"
#include "read/inflate_reader.h"
#include "read/input_format.h"
#include "read/nifti/nifti_header.h"
#include "read/raw_file.h"
#include "read/stored_volume_source.h"

namespace mvox {
namespace {

bool ends_with(const std::string& text, const char* suffix) {
  const std::string tail(suffix);
  if (text.size() < tail.size()) return false;
  for (std::size_t i = 0; i < tail.size(); ++i) {
    const char c = text[text.size() - tail.size() + i];
    if (std::tolower(static_cast<unsigned char>(c)) != tail[i]) return false;
  }
  return true;
}

// The header's bytes: the first 348, and 540 when sizeof_hdr says NIfTI-2.
NiftiHeader read_header(RawFile& file, bool gzipped) {
  unsigned char bytes[kNifti2Bytes];
  if (gzipped) {
    InflateReader inflate(file, 0, file.size_bytes());
    inflate.read(bytes, kNiftiMinBytes, kNiftiMinBytes, "a NIfTI header");
    const std::size_t size = nifti_header_size(bytes);
    if (size == kNifti2Bytes)
      inflate.read(bytes + kNiftiMinBytes, kNifti2Bytes - kNiftiMinBytes, kNifti2Bytes,
                   "a NIfTI-2 header");
    return parse_nifti_header(bytes, size == kNifti2Bytes ? kNifti2Bytes : kNiftiMinBytes,
                              file.name());
  }
  const std::size_t available =
      static_cast<std::size_t>(std::min<std::uint64_t>(file.size_bytes(), kNifti2Bytes));
  file.read_at(0, bytes, available);
  return parse_nifti_header(bytes, available, file.name());
}

// The .img beside a .hdr: the same name with .img (or .img.gz), in the case the .hdr's
// extension has.
std::string image_file_of(const std::string& header_path) {
  const std::string stem = header_path.substr(0, header_path.size() - 4);
  const bool upper = header_path.compare(header_path.size() - 4, 4, ".HDR") == 0;
  static const char* const kLower[] = {".img", ".img.gz"};
  static const char* const kUpper[] = {".IMG", ".IMG.GZ"};
  for (const char* extension : upper ? kUpper : kLower) {
    const std::string candidate = stem + extension;
    if (std::filesystem::exists(candidate))
      return resolve_data_file(header_path, std::filesystem::path(candidate).filename().string());
  }
  throw Error(header_path, "its samples are in a .img file beside it (ni1/ni2 magic), and " +
                               std::filesystem::path(stem + (upper ? ".IMG" : ".img"))
                                   .filename()
                                   .string() +
                               " does not exist");
}

}  // namespace

namespace {

std::unique_ptr<StoredVolumeSource> open_nifti(const std::string& path, bool pair, bool gzipped) {
  RawFile header_file(path);
  const NiftiHeader header = read_header(header_file, gzipped);
  if (pair == header.single_file)
    throw Error(path, pair ? "a .hdr file whose magic says the samples follow in the same file "
                             "(n+1/n+2); name it .nii"
                           : "a .nii file whose magic says its samples are in a .img file "
                             "(ni1/ni2); name it .hdr, beside its .img");

  StoredVolume volume = header.volume;
  StoredVolumeData data;
  data.header = path;
  data.path = pair ? image_file_of(path) : path;
  if (pair ? ends_with(data.path, ".gz") : gzipped) {
    // The whole file is one gzip stream; the samples start vox_offset bytes into it.
    volume.compression = Compression::gzip;
    data.skip_decompressed = header.vox_offset;
  } else {
    data.offset = header.vox_offset;
  }
  return std::make_unique<StoredVolumeSource>(volume, data);
}

}  // namespace

std::unique_ptr<StoredVolumeSource> open_nifti_volume(const std::string& path) {
  return open_nifti(path, ends_with(path, ".hdr"), ends_with(path, ".gz"));
}

std::unique_ptr<StoredVolumeSource> open_nifti_file(const std::string& path, bool gzipped) {
  return open_nifti(path, false, gzipped);
}

const InputFormat& nifti_volume_format() {
  static const InputFormat format{
      "NIfTI volume",
      [](const InputRequest& request) {
        return claims_headered_volume(request, "NIfTI", {".nii", ".nii.gz", ".hdr"});
      },
      [](const InputRequest& request) {
        return open_headered_volume(request, "NIfTI", {".nii", ".nii.gz", ".hdr"},
                                    open_nifti_volume);
      }};
  return format;
}

}  // namespace mvox
