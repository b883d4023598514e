#pragma once
// When the command line's INPUT is a DICOM series, and opening it as one.
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/dicom/dicom_volume_plan.h"

namespace mvox {

// The command line's DICOM options.
struct DicomChoice {
  bool force = false;      // --dicom: read INPUT as DICOM whatever it looks like
  std::string series_uid;  // --series UID; empty: the series with the most slices
  DicomNote note;          // where one-line remarks go (nowhere with --quiet)
};

// True when INPUT is DICOM without being told: some file it names (a directory contributes its
// regular, non-hidden files) has no slice image extension and either the "DICM" preamble or a
// .dcm/.dicom name. Images (PNG previews beside the series) are never opened for this. Entries
// that cannot be read (a FIFO, a dangling link) are passed over here; the DICOM row refuses
// them. False, without an error, when the inputs cannot be listed: the image reader reports that.
// The request's form looks at its listing, shared with the other rows (input_format.h).
class InputRequest;
bool is_dicom_input(const InputRequest& request);
bool is_dicom_input(const std::vector<std::string>& inputs);

struct InputFormat;

// The input-format row (read/input_format.h) of DICOM series. It claims the input with --dicom,
// or, without --raw, when is_dicom_input() says so; it opens a DicomSeriesSource over every file
// INPUT names (a directory's other files are offered too and skipped by content).
const InputFormat& dicom_series_format();

}  // namespace mvox
