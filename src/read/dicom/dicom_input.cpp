#include "read/dicom/dicom_input.h"

#include "error.h"
#include "read/dicom/dicom_file_scan.h"
#include "read/dicom/dicom_series_source.h"
#include "read/input_files.h"
#include "read/input_format.h"

namespace mvox {

bool is_dicom_input(const InputRequest& request) {
  const std::vector<std::string>* files = nullptr;
  try {
    // A FIFO or a dangling link among the files must not hide the series: with it refused here,
    // the folder would be read as images and called empty of slices. the DICOM row's own
    // listing refuses it, naming it.
    files = &request.files(InputKind::raw_files, BadEntries::skip);
  } catch (const Error&) {
    return false;
  }
  for (const std::string& file : *files) {
    if (has_slice_image_extension(file)) continue;
    if (has_dicom_extension(file) || has_dicom_preamble(file)) return true;
  }
  return false;
}

bool is_dicom_input(const std::vector<std::string>& inputs) {
  return is_dicom_input(InputRequest(inputs, InputOptions{}));
}

namespace {

bool claims(const InputRequest& request) {
  if (request.options().dicom.force) return true;
  return !request.options().raw && is_dicom_input(request);
}

OpenedInput open(const InputRequest& request) {
  const DicomChoice& choice = request.options().dicom;
  DicomOptions options;
  options.series_uid = choice.series_uid;
  options.label = inputs_label(request.inputs());
  options.note = choice.note;
  OpenedInput opened;
  opened.files = request.files(InputKind::raw_files);
  opened.source = std::make_unique<DicomSeriesSource>(opened.files, std::move(options));
  return opened;
}

}  // namespace

const InputFormat& dicom_series_format() {
  static const InputFormat format{"DICOM series", claims, open};
  return format;
}

}  // namespace mvox
