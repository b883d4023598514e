#include "read/dicom/dicom_volume_plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "error.h"
#include "mvox/assert.h"

namespace mvox {
namespace {

using Vec3 = std::array<double, 3>;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double length(const Vec3& a) { return std::sqrt(dot(a, a)); }
Vec3 scaled(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// %g keeps messages short: 0.9765625 stays exact, 12 stays 12.
std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string pixel_type_text(const DicomImageHeader& h) {
  return std::to_string(h.bits_allocated) + "-bit " + (h.is_signed ? "signed" : "unsigned");
}

std::string numbers_text(const double* values, std::size_t count) {
  std::string text;
  for (std::size_t i = 0; i < count; ++i) text += (i ? "\\" : "") + number_text(values[i]);
  return text;
}

bool nearly_equal(double a, double b, double tolerance) { return std::fabs(a - b) <= tolerance; }

// PASS 1: every file is like the first in what makes slices stack into one volume.
void check_alike(const std::vector<DicomImageHeader>& headers) {
  const DicomImageHeader& first = headers.front();
  const std::string like_first = " like the first slice (" + first.path + ")";
  for (const DicomImageHeader& h : headers) {
    if (&h == &first) continue;
    if (h.frames > 1 || first.frames > 1) {
      const DicomImageHeader& multi = h.frames > 1 ? h : first;
      throw Error(multi.path, "is a multi-frame file (" + std::to_string(multi.frames) +
                                  " frames) in a series of several files; mvox reads one "
                                  "multi-frame file alone");
    }
    if (h.columns != first.columns || h.rows != first.rows)
      throw Error(h.path, "image is " + std::to_string(h.columns) + "x" + std::to_string(h.rows) +
                              ", expected " + std::to_string(first.columns) + "x" +
                              std::to_string(first.rows) + like_first);
    if (h.bits_allocated != first.bits_allocated || h.is_signed != first.is_signed)
      throw Error(h.path, "pixels are " + pixel_type_text(h) + ", expected " +
                              pixel_type_text(first) + like_first);
    if (h.orientation.has_value() != first.orientation.has_value())
      throw Error(h.path, std::string(h.orientation ? "has" : "lacks") +
                              " ImageOrientationPatient, unlike the first slice (" + first.path +
                              ")");
    if (h.orientation) {
      for (int i = 0; i < 6; ++i)
        if (!nearly_equal((*h.orientation)[i], (*first.orientation)[i], 1e-4))
          throw Error(h.path, "orientation " + numbers_text(h.orientation->data(), 6) +
                                  " differs from " + numbers_text(first.orientation->data(), 6) +
                                  " of the first slice (" + first.path + ")");
    }
    const bool spacing_differs =
        h.pixel_spacing.has_value() != first.pixel_spacing.has_value() ||
        (h.pixel_spacing && (!nearly_equal((*h.pixel_spacing)[0], (*first.pixel_spacing)[0],
                                           1e-4 * (*first.pixel_spacing)[0]) ||
                             !nearly_equal((*h.pixel_spacing)[1], (*first.pixel_spacing)[1],
                                           1e-4 * (*first.pixel_spacing)[1])));
    if (spacing_differs) {
      auto text = [](const DicomImageHeader& x) {
        return x.pixel_spacing ? numbers_text(x.pixel_spacing->data(), 2) : std::string("none");
      };
      throw Error(h.path, "PixelSpacing " + text(h) + " differs from " + text(first) +
                              " of the first slice (" + first.path + ")");
    }
  }
}

// PASS 2: the voxel axes from the first file's orientation.
void set_axes(const DicomImageHeader& first, VolumeInfo& info) {
  if (!first.orientation) return;  // identity
  const auto& o = *first.orientation;
  Vec3 row{o[0], o[1], o[2]};
  Vec3 column{o[3], o[4], o[5]};
  const double row_length = length(row);
  const double column_length = length(column);
  // Writers round the cosines to a few digits, so lengths and the angle are checked loosely.
  if (!nearly_equal(row_length, 1, 1e-2) || !nearly_equal(column_length, 1, 1e-2) ||
      std::fabs(dot(row, column)) > 1e-2)
    throw Error(first.path, "ImageOrientationPatient " + numbers_text(o.data(), 6) +
                                " is not two perpendicular unit vectors");
  row = scaled(row, 1 / row_length);
  column = scaled(column, 1 / column_length);
  Vec3 normal = cross(row, column);
  normal = scaled(normal, 1 / length(normal));
  for (int i = 0; i < 3; ++i) {
    info.axes[0][i] = row[i];
    info.axes[1][i] = column[i];
    info.axes[2][i] = normal[i];
  }
}

Vec3 normal_of(const VolumeInfo& info) {
  return {info.axes[2][0], info.axes[2][1], info.axes[2][2]};
}

}  // namespace

DicomVolumePlan plan_dicom_volume(std::vector<DicomImageHeader> headers, const std::string& label,
                                  const DicomNote& note) {
  MVOX_ASSERT(!headers.empty());
  auto tell = [&](const std::string& line) {
    if (note) note(label + ": " + line);
  };
  DicomVolumePlan plan;
  plan.headers = std::move(headers);
  const std::vector<DicomImageHeader>& files = plan.headers;
  const DicomImageHeader& first = files.front();
  check_alike(files);
  VolumeInfo& info = plan.info;
  set_axes(first, info);
  const Vec3 normal = normal_of(info);

  // PASS 3: the slices, in order along the normal.
  for (std::size_t f = 0; f < files.size(); ++f)
    for (std::uint32_t frame = 0; frame < files[f].frames; ++frame) {
      DicomSliceRef slice;
      slice.header = f;
      slice.frame = frame;
      slice.mapping = {files[f].bits_allocated, files[f].bits_stored, files[f].is_signed,
                       files[f].rescale_slope, files[f].rescale_intercept};
      plan.slices.push_back(slice);
    }
  if (plan.slices.size() > std::numeric_limits<std::uint32_t>::max())
    throw Error(label, "more than 2^32-1 slices");
  std::vector<DicomSliceRef>& slices = plan.slices;
  const bool single_file = files.size() == 1;
  const auto missing_position =
      std::find_if(files.begin(), files.end(), [](const auto& h) { return !h.position; });
  const bool by_position = !single_file && missing_position == files.end();
  double z_spacing = 1;
  if (by_position) {
    for (DicomSliceRef& s : slices) s.position_mm = dot(*files[s.header].position, normal);
    std::stable_sort(slices.begin(), slices.end(),
                     [](const auto& a, const auto& b) { return a.position_mm < b.position_mm; });
    // The typical gap is the median: with a slice missing, the mean would make every gap look
    // uneven, where the median singles out the one that is.
    std::vector<double> gaps;
    for (std::size_t k = 1; k < slices.size(); ++k)
      gaps.push_back(slices[k].position_mm - slices[k - 1].position_mm);
    std::vector<double> sorted_gaps = gaps;
    std::nth_element(sorted_gaps.begin(), sorted_gaps.begin() + sorted_gaps.size() / 2,
                     sorted_gaps.end());
    const double typical_gap = sorted_gaps[sorted_gaps.size() / 2];
    for (std::size_t k = 1; k < slices.size(); ++k) {
      const DicomImageHeader& previous = files[slices[k - 1].header];
      const DicomImageHeader& current = files[slices[k].header];
      const double gap = gaps[k - 1];
      if (gap <= 1e-3 * typical_gap)
        throw Error(current.path, "lies at the same position along the slice normal (" +
                                      number_text(slices[k].position_mm) + " mm) as " +
                                      previous.path + ": two slices in one place");
      if (std::fabs(gap - typical_gap) > kDicomSliceGapTolerance * typical_gap)
        throw Error(current.path, "lies " + number_text(gap) + " mm from the previous slice (" +
                                      previous.path + ") where the series' slices are " +
                                      number_text(typical_gap) +
                                      " mm apart: uneven slice spacing or a missing slice");
    }
    // Every gap is within the tolerance of the median; their mean evens out rounded positions.
    const double mean_gap = (slices.back().position_mm - slices.front().position_mm) /
                            static_cast<double>(slices.size() - 1);
    z_spacing = mean_gap;
    // Positions that drift across the normal (a tilted CT gantry) shear the volume; the mesh
    // cannot show that, so say so when it exceeds half a pixel.
    const Vec3& origin = *files[slices.front().header].position;
    double drift = 0;
    for (const DicomSliceRef& s : slices) {
      const Vec3 offset = minus(minus(*files[s.header].position, origin),
                                scaled(normal, s.position_mm - slices.front().position_mm));
      drift = std::max(drift, length(offset));
    }
    const double half_pixel =
        first.pixel_spacing ? 0.5 * std::min((*first.pixel_spacing)[0], (*first.pixel_spacing)[1])
                            : 0.5;
    if (drift > half_pixel)
      tell("slice positions drift up to " + number_text(drift) +
           " mm across the slice normal (gantry tilt?); the mesh stacks the slices along the "
           "normal without that shear");
  } else {
    // Without positions: InstanceNumber, else the file names; the spacing from the header.
    std::string order = "file name";
    if (!single_file) {
      const bool numbered = std::all_of(
          files.begin(), files.end(), [](const auto& h) { return h.instance_number.has_value(); });
      if (numbered) {
        order = "InstanceNumber";
        std::stable_sort(slices.begin(), slices.end(), [&](const auto& a, const auto& b) {
          return *files[a.header].instance_number < *files[b.header].instance_number;
        });
        for (std::size_t k = 1; k < slices.size(); ++k)
          if (*files[slices[k].header].instance_number ==
              *files[slices[k - 1].header].instance_number)
            throw Error(files[slices[k].header].path,
                        "has the same InstanceNumber (" +
                            std::to_string(*files[slices[k].header].instance_number) + ") as " +
                            files[slices[k - 1].header].path +
                            ", and the series has no positions to order them by");
      }
    }
    std::string spacing_source = "none given, 1";
    if (first.spacing_between_slices) {
      z_spacing = *first.spacing_between_slices;
      spacing_source = "SpacingBetweenSlices";
    } else if (first.slice_thickness) {
      z_spacing = *first.slice_thickness;
      spacing_source = "SliceThickness";
    }
    if (slices.size() > 1) {
      if (single_file)
        tell("frames of " + first.path + " taken in file order, " + number_text(z_spacing) +
             " mm apart (" + spacing_source + ")");
      else
        tell("no ImagePositionPatient in " + missing_position->path + ": slices ordered by " +
             order + ", " + number_text(z_spacing) + " mm apart (" + spacing_source + ")");
    }
    // A multi-frame file's frames stack along the normal from its position.
    for (std::size_t k = 0; k < slices.size(); ++k)
      slices[k].position_mm = static_cast<double>(k) * z_spacing;
  }

  // PASS 4: geometry and sample type.
  info.width = first.columns;
  info.height = first.rows;
  info.depth = static_cast<std::uint32_t>(slices.size());
  if (first.pixel_spacing) {
    info.spacing[0] = (*first.pixel_spacing)[1];  // column spacing: between columns, along x
    info.spacing[1] = (*first.pixel_spacing)[0];  // row spacing: between rows, along y
  } else {
    tell(first.unusable_pixel_spacing.empty()
             ? "no PixelSpacing in " + first.path + ": pixels taken as 1 x 1 mm"
             : "PixelSpacing '" + first.unusable_pixel_spacing + "' of " + first.path +
                   " is not two positive numbers: pixels taken as 1 x 1 mm");
  }
  info.spacing[2] = z_spacing;
  if (const auto& position = files[slices.front().header].position)
    for (int i = 0; i < 3; ++i) info.origin[i] = (*position)[i];
  std::vector<DicomValueMapping> mappings;
  for (const DicomSliceRef& s : slices) mappings.push_back(s.mapping);
  info.type = exact_sample_type(mappings);
  return plan;
}

}  // namespace mvox
