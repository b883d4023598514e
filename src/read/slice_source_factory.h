#pragma once
// Picks and opens the slice reader for the command line's INPUT arguments and --raw option.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "read/dicom/dicom_input.h"
#include "mvox/slice_source.h"
#include "read/raw/raw_format.h"

namespace mvox {

// - raw with depth (WxHxD:TYPE): RawVolumeSource; `inputs` must name exactly one file (a glob
//   matching one file is fine, a directory is not).
// - raw without depth (WxH:TYPE): RawSlicesSource over list_input_files(inputs, raw_files),
//   so a directory contributes all its regular, non-hidden files.
// - no raw, and dicom.force or is_dicom_input(inputs): DicomSeriesSource (open_dicom_input).
// - no raw: list_input_files(inputs, image_stack), then open_volume_files (volume_files.h:
//   NRRD, MetaImage, TIFF stacks) or else ImageStackSource.
// - raw with an input named like a NRRD or MetaImage file: refused (subject "--raw").
// Throws mvox::Error from the file listing and the readers' constructors, and for --dicom with
// --raw or --series with input that is not DICOM.
std::unique_ptr<SliceSource> open_slice_source(const std::vector<std::string>& inputs,
                                               const std::optional<RawFormat>& raw,
                                               const DicomChoice& dicom = {});

// An open input and every file it reads.
struct OpenedInput {
  std::unique_ptr<SliceSource> source;
  // The slice files, headers and data files the source reads (for DICOM, every file INPUT
  // offered, DICOM or not), so that no output can replace one of them (output_targets.h).
  std::vector<std::string> files;
};

// open_slice_source, with the files it reads.
OpenedInput open_input(const std::vector<std::string>& inputs,
                       const std::optional<RawFormat>& raw, const DicomChoice& dicom = {});

}  // namespace mvox
