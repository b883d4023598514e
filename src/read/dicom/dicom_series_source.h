#pragma once
// Reads a DICOM series as a volume: the files of one SeriesInstanceUID, ordered by position
// along the slice normal, in modality units (RescaleSlope/RescaleIntercept applied), placed in
// patient coordinates (LPS, mm).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "read/dicom/dicom_pixel_reader.h"
#include "read/dicom/dicom_volume_plan.h"
#include "read/range_readable.h"

namespace mvox {

struct DicomOptions {
  // The SeriesInstanceUID to read; empty: the series with the most slices.
  std::string series_uid;
  // Names the input in notes and in errors about the input as a whole.
  std::string label = "INPUT";
  // One-line remarks: which series was chosen when there are several, fallbacks taken
  // (see plan_dicom_volume). May be empty.
  DicomNote note;
};

// `files`: candidate files, e.g. a directory's listing. Each is scanned, headers only: files that
// are not DICOM (no preamble, and not a .dcm/.dicom name, and no plausible data set), and DICOM
// objects without an image (DICOMDIR, reports), are skipped; a .dcm/.dicom file or a file with the
// preamble that is truncated or malformed is an error. The images are grouped by
// SeriesInstanceUID and one series is planned (plan_dicom_volume); info() is exact from then on.
// Memory: the headers of the chosen series, one decoded frame and one slice of samples
// (allocated at the first slice), and GDCM's copy of one file and of one frame while it decodes
// (working_bytes()).
// Throws mvox::Error: naming `options.label` when no file is a DICOM image; naming "--series"
// with the available series and their slice counts when options.series_uid is not among them;
// naming the file for everything plan_dicom_volume and read_dicom_image_header refuse, and, from
// next_slice, for pixel data GDCM cannot decode.
// Its files are read from anywhere (RangeReadable): each slab worker decodes its own slices,
// with a DICOM reader of its own, from the plan the source made (shared, not copied).
class DicomSeriesSource : public SliceSource, public RangeReadable {
 public:
  DicomSeriesSource(const std::vector<std::string>& files, DicomOptions options);

  const VolumeInfo& info() const override { return plan_->info; }
  bool next_slice(SliceView* slice) override;
  std::uint64_t working_bytes() const override;

  bool range_readable() const override { return true; }
  std::unique_ptr<SliceSource> open_range(std::uint32_t first, std::uint32_t end) const override;

  const DicomVolumePlan& plan() const { return *plan_; }
  const std::string& series_uid() const { return plan_->headers.front().series_uid; }
  // "CT", "MR", ... as the first slice's header says; empty when it says nothing.
  const std::string& modality() const { return plan_->headers.front().modality; }

 private:
  // Slices [first, end) of `whole`'s series.
  DicomSeriesSource(const DicomSeriesSource& whole, std::uint32_t first, std::uint32_t end);

  std::shared_ptr<const DicomVolumePlan> plan_;
  DicomPixelReader reader_;
  std::vector<char> decoded_;           // GDCM's samples of the current frame
  std::vector<unsigned char> samples_;  // the current slice in info().type
  std::size_t next_index_ = 0;
  std::size_t end_index_ = 0;             // one past the last slice next_slice returns
  std::uint64_t largest_file_bytes_ = 0;  // of the chosen series' files
};

}  // namespace mvox
