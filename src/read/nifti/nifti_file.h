#pragma once
// Opens a NIfTI-1 or NIfTI-2 volume: a .nii file (header and samples), a gzipped .nii.gz, or a
// .hdr header with its samples in the .img (or .img.gz) beside it.
#include <memory>
#include <string>

#include "read/stored_volume_source.h"

namespace mvox {

// Reads and checks the header (parse_nifti_header; through zlib for .nii.gz) and returns a
// StoredVolumeSource over the samples, scaled by scl_slope and scl_inter when the header says
// so, placed by the sform, else the qform, else the voxel sizes. Throws mvox::Error naming the
// file for a header problem, a missing .img, or samples that are short or corrupt.
std::unique_ptr<StoredVolumeSource> open_nifti_volume(const std::string& path);

// The same for a one-file NIfTI (header and samples), gzipped or not whatever its name: for
// callers whose path says nothing (the fuzz target's in-memory file).
std::unique_ptr<StoredVolumeSource> open_nifti_file(const std::string& path, bool gzipped);

struct InputFormat;

// The input-format row (read/input_format.h) of NIfTI volumes: one .nii, .nii.gz or .hdr file,
// which takes no --raw.
const InputFormat& nifti_volume_format();

}  // namespace mvox
