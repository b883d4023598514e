#include "dicom_series.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "error.h"

namespace mvox::test::dicom_series {

namespace fs = std::filesystem;

namespace {

double sample_at(const SliceView& slice, std::uint32_t x, std::uint32_t y) {
  const char* at = static_cast<const char*>(slice.samples) + y * slice.row_stride_bytes;
  switch (slice.type) {
    case SampleType::u8: return static_cast<unsigned char>(at[x]);
    case SampleType::u16: {
      std::uint16_t v;
      std::memcpy(&v, at + 2 * x, 2);
      return v;
    }
    case SampleType::i16: {
      std::int16_t v;
      std::memcpy(&v, at + 2 * x, 2);
      return v;
    }
    case SampleType::f32: {
      float v;
      std::memcpy(&v, at + 4 * x, 4);
      return v;
    }
  }
  return std::nan("");
}

}  // namespace

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

std::vector<double> read_values(SliceSource& source) {
  std::vector<double> values;
  SliceView slice;
  while (source.next_slice(&slice)) {
    EXPECT_EQ(slice.width, source.info().width);
    EXPECT_EQ(slice.type, source.info().type);
    for (std::uint32_t y = 0; y < slice.height; ++y)
      for (std::uint32_t x = 0; x < slice.width; ++x) values.push_back(sample_at(slice, x, y));
  }
  return values;
}

DicomSeriesSource open_series(const std::string& directory, std::vector<std::string>* notes,
                              const std::string& series_uid) {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(directory))
    files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  DicomOptions options;
  options.label = directory;
  options.series_uid = series_uid;
  if (notes) options.note = [notes](const std::string& line) { notes->push_back(line); };
  return DicomSeriesSource(files, options);
}

void expect_error(const std::function<void()>& action, const std::string& subject,
                  const std::string& words) {
  try {
    action();
    ADD_FAILURE() << "no error; expected one about " << subject << " (" << words << ")";
  } catch (const Error& e) {
    EXPECT_EQ(e.subject(), subject) << e.what();
    EXPECT_NE(e.problem().find(words), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

std::vector<std::int64_t> pattern(std::uint32_t width, std::uint32_t height, std::int64_t slice,
                                  std::int64_t base) {
  std::vector<std::int64_t> values;
  for (std::uint32_t y = 0; y < height; ++y)
    for (std::uint32_t x = 0; x < width; ++x) values.push_back(base + 300 * slice + 17 * y + x);
  return values;
}

void write_series(const std::string& directory, const std::string& prefix, DicomSliceSpec spec,
                  int count, const Vec3& origin, double gap, std::vector<int> order) {
  const auto o = spec.orientation.value_or(std::array<double, 6>{1, 0, 0, 0, 1, 0});
  const Vec3 normal = cross({o[0], o[1], o[2]}, {o[3], o[4], o[5]});
  if (order.empty())
    for (int k = 0; k < count; ++k) order.push_back(k);
  for (int i = 0; i < count; ++i) {
    const int k = order[i];
    spec.position = Vec3{origin[0] + k * gap * normal[0], origin[1] + k * gap * normal[1],
                         origin[2] + k * gap * normal[2]};
    spec.stored = pattern(spec.width, spec.height, k);
    write_dicom(directory + "/" + prefix + std::to_string(i) + ".dcm", spec);
  }
}

std::string dataset(const std::string& name) {
  return std::string(MVOX_SHARED_DATASETS) + "/" + name;
}

}  // namespace mvox::test::dicom_series
