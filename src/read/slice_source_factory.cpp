#include "read/slice_source_factory.h"

#include <filesystem>
#include <system_error>
#include <utility>

#include "error.h"
#include "read/image_stack/image_stack_source.h"
#include "read/input_files.h"
#include "read/raw/raw_slices_source.h"
#include "read/raw/raw_volume_source.h"
#include "read/volume_files.h"

namespace mvox {

std::unique_ptr<SliceSource> open_slice_source(const std::vector<std::string>& inputs,
                                               const std::optional<RawFormat>& raw,
                                               const DicomChoice& dicom) {
  return open_input(inputs, raw, dicom).source;
}

OpenedInput open_input(const std::vector<std::string>& inputs, const std::optional<RawFormat>& raw,
                       const DicomChoice& dicom) {
  OpenedInput opened;
  if (dicom.force && raw) throw Error("--dicom", "cannot be combined with --raw");
  if (!raw && (dicom.force || is_dicom_input(inputs))) {
    opened.files = list_input_files(inputs, InputKind::raw_files);
    opened.source = open_dicom_input(inputs, dicom);
    return opened;
  }
  if (!dicom.series_uid.empty())
    throw Error("--series",
                "applies to DICOM input only, and INPUT is not DICOM (use --dicom "
                "for DICOM files without the DICM preamble or a .dcm name)");
  if (!raw) {
    opened.files = list_input_files(inputs, InputKind::image_stack);
    std::vector<std::string> data_files;
    opened.source = open_volume_files(opened.files, &data_files);
    opened.files.insert(opened.files.end(), data_files.begin(), data_files.end());
    if (!opened.source) opened.source = std::make_unique<ImageStackSource>(opened.files);
    return opened;
  }
  for (const std::string& input : inputs) {
    if (const HeaderedFormat format = headered_format(input); format != HeaderedFormat::none) {
      throw Error("--raw", input + " is a " + headered_format_name(format) +
                               " file with its own header; leave --raw out");
    }
  }
  if (raw->depth == 0) {
    opened.files = list_input_files(inputs, InputKind::raw_files);
    opened.source = std::make_unique<RawSlicesSource>(opened.files, *raw);
    return opened;
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
  opened.files = list_input_files(inputs, InputKind::raw_files);
  if (opened.files.size() != 1) {
    throw Error(inputs[0], "matches " + std::to_string(opened.files.size()) + " files; " +
                               volume_text + " reads one volume file");
  }
  opened.source = std::make_unique<RawVolumeSource>(opened.files[0], *raw);
  return opened;
}

}  // namespace mvox
