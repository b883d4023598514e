#include "read/dicom/dicom_series_source.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <utility>

#include "error.h"
#include "read/buffer_allocation.h"
#include "read/dicom/dicom_file_scan.h"

namespace mvox {
namespace {

struct Series {
  std::string uid;
  std::vector<DicomImageHeader> headers;  // in the order of `files`
  std::uint64_t slices = 0;               // frames of all its files
};

std::string uid_text(const std::string& uid) {
  return uid.empty() ? "(no SeriesInstanceUID)" : uid;
}

std::string slices_text(std::uint64_t count) {
  return std::to_string(count) + (count == 1 ? " slice" : " slices");
}

// "1.2.3 'AX T1' (24 slices)": the UID to type, the description to recognise it by.
std::string series_text(const Series& s) {
  const std::string& description = s.headers.front().series_description;
  return uid_text(s.uid) + (description.empty() ? "" : " '" + description + "'") + " (" +
         slices_text(s.slices) + ")";
}

// At most `shown` series, then how many more: one line even for a folder of a whole study.
std::string list_text(const std::vector<const Series*>& list, std::size_t shown = 6) {
  std::string text;
  for (std::size_t i = 0; i < list.size() && i < shown; ++i)
    text += (i ? ", " : "") + series_text(*list[i]);
  if (list.size() > shown) text += ", and " + std::to_string(list.size() - shown) + " more";
  return text;
}

// Groups the DICOM images among `files` by series, largest first (ties by UID).
std::vector<Series> scan_series(const std::vector<std::string>& files, const std::string& label) {
  std::map<std::string, Series> by_uid;
  for (const std::string& path : files) {
    std::optional<DicomImageHeader> header =
        read_dicom_image_header(path, has_dicom_extension(path));
    if (!header) continue;
    Series& series = by_uid[header->series_uid];
    series.uid = header->series_uid;
    series.slices += header->frames;
    series.headers.push_back(std::move(*header));
  }
  if (by_uid.empty())
    throw Error(label, "no DICOM image among " + std::to_string(files.size()) +
                           (files.size() == 1 ? " file" : " files") +
                           " (DICOM files have the DICM preamble or a .dcm name)");
  std::vector<Series> series;
  for (auto& entry : by_uid) series.push_back(std::move(entry.second));
  std::stable_sort(series.begin(), series.end(),
                   [](const Series& a, const Series& b) { return a.slices > b.slices; });
  return series;
}

}  // namespace

DicomSeriesSource::DicomSeriesSource(const std::vector<std::string>& files, DicomOptions options) {
  std::vector<Series> series = scan_series(files, options.label);
  std::vector<const Series*> all;
  for (const Series& s : series) all.push_back(&s);

  std::size_t chosen = 0;  // the largest
  if (!options.series_uid.empty()) {
    const auto found = std::find_if(series.begin(), series.end(),
                                    [&](const Series& s) { return s.uid == options.series_uid; });
    if (found == series.end())
      throw Error("--series", "no series " + options.series_uid + " in " + options.label +
                                  "; it holds " + list_text(all, all.size()));
    chosen = static_cast<std::size_t>(found - series.begin());
  } else if (series.size() > 1 && options.note) {
    std::vector<const Series*> others;
    for (std::size_t i = 1; i < series.size(); ++i) others.push_back(&series[i]);
    options.note(options.label + ": " + std::to_string(series.size()) +
                 " DICOM series; reading the largest, " + series_text(series[0]) + "; also " +
                 list_text(others) + "; choose one with --series UID");
  }
  plan_ = std::make_shared<const DicomVolumePlan>(
      plan_dicom_volume(std::move(series[chosen].headers), options.label, options.note));
  end_index_ = plan_->slices.size();
  for (const DicomImageHeader& header : plan_->headers) {
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(header.path, error);
    if (!error) largest_file_bytes_ = std::max<std::uint64_t>(largest_file_bytes_, bytes);
  }
  reader_.load(plan_->headers.front().path);
}

DicomSeriesSource::DicomSeriesSource(const DicomSeriesSource& whole, std::uint32_t first,
                                     std::uint32_t end)
    : plan_(whole.plan_),
      next_index_(first),
      end_index_(std::min<std::size_t>(end, whole.plan_->slices.size())),
      largest_file_bytes_(whole.largest_file_bytes_) {}

std::unique_ptr<SliceSource> DicomSeriesSource::open_range(std::uint32_t first,
                                                           std::uint32_t end) const {
  return std::unique_ptr<SliceSource>(new DicomSeriesSource(*this, first, end));
}

std::uint64_t DicomSeriesSource::working_bytes() const {
  const std::uint64_t slice =
      std::uint64_t{plan_->info.width} * plan_->info.height * sample_bytes(plan_->info.type);
  const std::uint64_t frame = dicom_frame_bytes(plan_->headers.front());
  // Our decoded frame and slice; GDCM's copy of the file and of the frame it decodes.
  return slice + 2 * frame + largest_file_bytes_;
}

bool DicomSeriesSource::next_slice(SliceView* slice) {
  if (next_index_ >= end_index_) return false;
  const DicomVolumePlan& plan = *plan_;
  const DicomSliceRef& ref = plan.slices[next_index_];
  reader_.read_frame(plan.headers[ref.header], ref.frame, decoded_);
  const std::size_t count = std::size_t{plan.info.width} * plan.info.height;
  if (samples_.empty())
    resize_buffer(samples_, std::uint64_t{count} * sample_bytes(plan.info.type),
                  plan.headers[ref.header].path, "a slice");
  rescale_samples(decoded_.data(), count, ref.mapping, plan.info.type, samples_.data());
  slice->samples = samples_.data();
  slice->width = plan.info.width;
  slice->height = plan.info.height;
  slice->row_stride_bytes = std::size_t{plan.info.width} * sample_bytes(plan.info.type);
  slice->type = plan.info.type;
  ++next_index_;
  return true;
}

}  // namespace mvox
