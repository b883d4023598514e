#include "slice_source_factory.h"

#include <filesystem>
#include <system_error>
#include <utility>

#include "error.h"
#include "image_stack_source.h"
#include "input_files.h"
#include "raw_slices_source.h"
#include "raw_volume_source.h"
#include "volume_files.h"

namespace mvox {

std::unique_ptr<SliceSource> open_slice_source(const std::vector<std::string>& inputs,
                                               const std::optional<RawFormat>& raw,
                                               const DicomChoice& dicom) {
  if (dicom.force && raw) throw Error("--dicom", "cannot be combined with --raw");
  if (!raw && (dicom.force || is_dicom_input(inputs))) return open_dicom_input(inputs, dicom);
  if (!dicom.series_uid.empty())
    throw Error("--series",
                "applies to DICOM input only, and INPUT is not DICOM (use --dicom "
                "for DICOM files without the DICM preamble or a .dcm name)");
  if (!raw) {
    std::vector<std::string> files = list_input_files(inputs, InputKind::image_stack);
    if (std::unique_ptr<SliceSource> volume = open_volume_files(files)) return volume;
    return std::make_unique<ImageStackSource>(std::move(files));
  }
  for (const std::string& input : inputs) {
    if (const HeaderedFormat format = headered_format(input); format != HeaderedFormat::none) {
      throw Error("--raw", input + " is a " + headered_format_name(format) +
                               " file with its own header; leave --raw out");
    }
  }
  if (raw->depth == 0) {
    return std::make_unique<RawSlicesSource>(list_input_files(inputs, InputKind::raw_files), *raw);
  }

  const std::string volume_text = "--raw " + raw_format_text(*raw);
  if (inputs.size() != 1) {
    throw Error("INPUT", volume_text + " reads one volume file, got " +
                             std::to_string(inputs.size()) + " inputs");
  }
  std::error_code error;
  if (std::filesystem::is_directory(inputs[0], error)) {
    throw Error(inputs[0], "is a directory; " + volume_text + " reads one volume file");
  }
  const std::vector<std::string> files = list_input_files(inputs, InputKind::raw_files);
  if (files.size() != 1) {
    throw Error(inputs[0], "matches " + std::to_string(files.size()) + " files; " + volume_text +
                               " reads one volume file");
  }
  return std::make_unique<RawVolumeSource>(files[0], *raw);
}

}  // namespace mvox
