#pragma once
// Turns the headers of one DICOM series into a volume: the slice order (by position along the
// slice normal), the voxel geometry in patient coordinates, and the sample type. Pure: it reads
// no file, so every rule can be checked on headers alone.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/dicom/dicom_header.h"
#include "read/dicom/dicom_values.h"

namespace mvox {

// One-line remarks for the user (a fallback taken, an oddity accepted); may be empty.
using DicomNote = std::function<void(const std::string& line)>;

struct DicomSliceRef {
  std::size_t header = 0;     // index into DicomVolumePlan::headers
  std::uint32_t frame = 0;    // frame within that file (0 for single-frame files)
  double position_mm = 0;     // along the slice normal; the sort key (0 without positions)
  DicomValueMapping mapping;  // that file's stored values to modality values
};

struct DicomVolumePlan {
  std::vector<DicomImageHeader> headers;
  std::vector<DicomSliceRef> slices;  // volume order: z = 0, 1, ...
  // width = Columns, height = Rows, depth = slices; type = exact_sample_type of all mappings;
  // spacing x = PixelSpacing[1] (between columns), y = PixelSpacing[0] (between rows), z = the
  // mean distance between consecutive positions (first to last, over the gaps); origin = the first
  // slice's ImagePositionPatient; axes = row cosine, column cosine, their cross product (the
  // normal). Patient coordinates: LPS, millimetres.
  VolumeInfo info;
};

// Slices whose distance to the previous one differs from the median distance by more than this
// fraction of it are refused (a missing slice shows as 100%).
constexpr double kDicomSliceGapTolerance = 0.10;

// Plans the volume of one series. `headers` are the series' image files in file-name order
// (used only when nothing else orders them); `label` names the input in notes.
// Order: by ImagePositionPatient projected on the normal (cross(row cosine, column cosine), or
// +z without ImageOrientationPatient), ascending; when a file lacks a position: by
// InstanceNumber, else by file name, with a note; z spacing then comes from SpacingBetweenSlices,
// SliceThickness or 1, with a note. A single multi-frame file gives its frames as slices, spaced
// like that fallback.
// Throws mvox::Error naming the offending file when slices differ from the first in size, pixel
// type (BitsAllocated, signedness), orientation or PixelSpacing; when two slices share a
// position (within 0.1% of the median gap) or an InstanceNumber (in that fallback); when a gap is
// uneven beyond kDicomSliceGapTolerance; when ImageOrientationPatient is not two perpendicular
// unit vectors; or when a multi-frame file is one of several.
// Notes: a missing or unusable PixelSpacing (1 x 1 used), the position fallbacks, and slices
// offset across the normal by more than half a pixel (gantry tilt: the mesh stacks them along
// the normal).
DicomVolumePlan plan_dicom_volume(std::vector<DicomImageHeader> headers, const std::string& label,
                                  const DicomNote& note);

}  // namespace mvox
