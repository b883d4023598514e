#include "read/dicom/dicom_input.h"

#include "read/dicom/dicom_file_scan.h"
#include "read/dicom/dicom_series_source.h"
#include "error.h"
#include "read/input_files.h"

namespace mvox {
bool is_dicom_input(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  try {
    // A FIFO or a dangling link among the files must not hide the series: with it refused here,
    // the folder would be read as images and called empty of slices. open_dicom_input's own
    // listing refuses it, naming it.
    files = list_input_files(inputs, InputKind::raw_files, BadEntries::skip);
  } catch (const Error&) {
    return false;
  }
  for (const std::string& file : files) {
    if (has_slice_image_extension(file)) continue;
    if (has_dicom_extension(file) || has_dicom_preamble(file)) return true;
  }
  return false;
}

std::unique_ptr<SliceSource> open_dicom_input(const std::vector<std::string>& inputs,
                                              const DicomChoice& choice) {
  DicomOptions options;
  options.series_uid = choice.series_uid;
  options.label = inputs_label(inputs);
  options.note = choice.note;
  return std::make_unique<DicomSeriesSource>(list_input_files(inputs, InputKind::raw_files),
                                             std::move(options));
}

}  // namespace mvox
