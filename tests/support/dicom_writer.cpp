#include "dicom_writer.h"

#include <gdcmImageChangeTransferSyntax.h>
#include <gdcmImageReader.h>
#include <gdcmImageWriter.h>
#include <gdcmTrace.h>
#include <gdcmTransferSyntax.h>
#include <gdcmWriter.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace mvox::test {
namespace {

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

template <std::size_t count>
std::string numbers_text(const std::array<double, count>& values) {
  std::string text;
  for (std::size_t i = 0; i < count; ++i) text += (i ? "\\" : "") + number_text(values[i]);
  return text;
}

void put_text(gdcm::DataSet& data_set, std::uint16_t group, std::uint16_t element, gdcm::VR vr,
              std::string value) {
  // Values have even lengths: UIDs are padded with NUL, text with a space (PS3.5 6.2).
  if (value.size() % 2) value += vr == gdcm::VR::UI ? '\0' : ' ';
  gdcm::DataElement e(gdcm::Tag(group, element));
  e.SetVR(vr);
  e.SetByteValue(value.data(), static_cast<std::uint32_t>(value.size()));
  data_set.Insert(e);
}

void put_us(gdcm::DataSet& data_set, std::uint16_t group, std::uint16_t element,
            std::uint16_t value) {
  gdcm::DataElement e(gdcm::Tag(group, element));
  e.SetVR(gdcm::VR::US);
  e.SetByteValue(reinterpret_cast<const char*>(&value), 2);  // native = little endian here
  data_set.Insert(e);
}

std::string next_instance_uid() {
  static std::atomic<unsigned> counter{0};
  return "1.2.826.0.1.3680043.10.543.2." + std::to_string(++counter);
}

std::vector<char> pixel_bytes(const DicomSliceSpec& spec) {
  const std::size_t count = std::size_t{spec.width} * spec.height * spec.frames;
  const std::size_t bytes_per_sample = spec.bits_allocated / 8u;
  std::vector<char> bytes(count * bytes_per_sample, 0);
  for (std::size_t i = 0; i < count && i < spec.stored.size(); ++i) {
    const auto value = static_cast<std::uint64_t>(spec.stored[i]);
    for (std::size_t b = 0; b < bytes_per_sample; ++b)  // little endian, like the host
      bytes[i * bytes_per_sample + b] = static_cast<char>((value >> (8 * b)) & 0xFF);
  }
  return bytes;
}

// Leaves only the data set: drops the preamble, "DICM" and the file meta group, whose length is
// the value of its first element (0002,0000), an explicit VR UL at byte 132 (PS3.10 7.1).
void strip_meta(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  ASSERT_GE(bytes.size(), 144u);
  std::uint32_t group_length = 0;
  for (int b = 3; b >= 0; --b)
    group_length = group_length << 8 | static_cast<unsigned char>(bytes[140 + b]);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(144 + group_length);
}

}  // namespace

void write_dicom(const std::string& path, const DicomSliceSpec& spec) {
  gdcm::Trace::SetWarning(false);
  gdcm::DataSet ds;
  put_text(ds, 0x0008, 0x0016, gdcm::VR::UI, spec.sop_class_uid);
  put_text(ds, 0x0008, 0x0018, gdcm::VR::UI, next_instance_uid());
  put_text(ds, 0x0008, 0x0060, gdcm::VR::CS, spec.modality);
  if (!spec.series_description.empty())
    put_text(ds, 0x0008, 0x103E, gdcm::VR::LO, spec.series_description);
  if (spec.spacing_between_slices)
    put_text(ds, 0x0018, 0x0088, gdcm::VR::DS, number_text(*spec.spacing_between_slices));
  put_text(ds, 0x0020, 0x000D, gdcm::VR::UI, "1.2.826.0.1.3680043.10.543.3");
  put_text(ds, 0x0020, 0x000E, gdcm::VR::UI, spec.series_uid);
  if (spec.instance_number)
    put_text(ds, 0x0020, 0x0013, gdcm::VR::IS, std::to_string(*spec.instance_number));
  if (spec.position) put_text(ds, 0x0020, 0x0032, gdcm::VR::DS, numbers_text(*spec.position));
  if (spec.orientation) put_text(ds, 0x0020, 0x0037, gdcm::VR::DS, numbers_text(*spec.orientation));
  if (spec.with_image) {
    put_us(ds, 0x0028, 0x0002, spec.samples_per_pixel);
    put_text(ds, 0x0028, 0x0004, gdcm::VR::CS, spec.photometric);
    if (spec.frames > 1) put_text(ds, 0x0028, 0x0008, gdcm::VR::IS, std::to_string(spec.frames));
    put_us(ds, 0x0028, 0x0010, static_cast<std::uint16_t>(spec.height));
    put_us(ds, 0x0028, 0x0011, static_cast<std::uint16_t>(spec.width));
    if (spec.pixel_spacing)
      put_text(ds, 0x0028, 0x0030, gdcm::VR::DS, numbers_text(*spec.pixel_spacing));
    put_us(ds, 0x0028, 0x0100, spec.bits_allocated);
    put_us(ds, 0x0028, 0x0101, spec.bits_stored);
    put_us(ds, 0x0028, 0x0102, static_cast<std::uint16_t>(spec.bits_stored - 1));
    put_us(ds, 0x0028, 0x0103, spec.is_signed ? 1 : 0);
    if (spec.intercept) put_text(ds, 0x0028, 0x1052, gdcm::VR::DS, number_text(*spec.intercept));
    if (spec.slope) put_text(ds, 0x0028, 0x1053, gdcm::VR::DS, number_text(*spec.slope));
    std::vector<char> bytes = pixel_bytes(spec);
    if (spec.samples_per_pixel > 1) bytes.resize(bytes.size() * spec.samples_per_pixel, 0);
    gdcm::DataElement pixels(gdcm::Tag(0x7FE0, 0x0010));
    pixels.SetVR(spec.bits_allocated == 8 ? gdcm::VR::OB : gdcm::VR::OW);
    pixels.SetByteValue(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
    ds.Insert(pixels);
  }

  gdcm::Writer writer;
  writer.SetFileName(path.c_str());
  writer.GetFile().SetDataSet(ds);
  writer.GetFile().GetHeader().SetDataSetTransferSyntax(
      gdcm::TransferSyntax::GetTSType(spec.transfer_syntax_uid.c_str()));
  if (!writer.Write()) ADD_FAILURE() << "GDCM cannot write " << path;
  if (!spec.with_meta) strip_meta(path);
}

bool recode(const std::string& in, const std::string& out, const std::string& transfer_syntax_uid) {
  gdcm::ImageReader reader;
  reader.SetFileName(in.c_str());
  if (!reader.Read()) {
    ADD_FAILURE() << "GDCM cannot read " << in;
    return false;
  }
  gdcm::ImageChangeTransferSyntax change;
  change.SetTransferSyntax(gdcm::TransferSyntax::GetTSType(transfer_syntax_uid.c_str()));
  change.SetInput(reader.GetImage());
  if (!change.Change()) {
    ADD_FAILURE() << "GDCM cannot recode " << in << " to " << transfer_syntax_uid;
    return false;
  }
  gdcm::ImageWriter writer;
  writer.SetFileName(out.c_str());
  writer.SetFile(reader.GetFile());
  writer.SetImage(change.GetOutput());
  if (!writer.Write()) {
    ADD_FAILURE() << "GDCM cannot write " << out;
    return false;
  }
  return true;
}

std::array<double, 6> oblique_orientation(double about_x_deg, double about_y_deg,
                                          double about_z_deg) {
  const double kRadians = 3.14159265358979323846 / 180;
  const double a = about_x_deg * kRadians, b = about_y_deg * kRadians, c = about_z_deg * kRadians;
  // R = Rz * Ry * Rx; its first two columns are the rotated x and y axes.
  const double rx[3][3] = {
      {1, 0, 0}, {0, std::cos(a), -std::sin(a)}, {0, std::sin(a), std::cos(a)}};
  const double ry[3][3] = {
      {std::cos(b), 0, std::sin(b)}, {0, 1, 0}, {-std::sin(b), 0, std::cos(b)}};
  const double rz[3][3] = {
      {std::cos(c), -std::sin(c), 0}, {std::sin(c), std::cos(c), 0}, {0, 0, 1}};
  double yx[3][3] = {}, r[3][3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) yx[i][j] += ry[i][k] * rx[k][j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[i][j] += rz[i][k] * yx[k][j];
  return {r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1]};
}

void write_dicom_series(const std::string& directory, const std::string& samples,
                        std::uint32_t width, std::uint32_t height, std::uint32_t depth,
                        const std::function<std::string(std::uint32_t)>& syntax_of) {
  std::filesystem::create_directories(directory);
  const std::size_t slice = std::size_t{width} * height;
  for (std::uint32_t z = 0; z < depth; ++z) {
    DicomSliceSpec spec;
    spec.width = width;
    spec.height = height;
    for (std::size_t i = 0; i < slice; ++i)
      spec.stored.push_back(static_cast<unsigned char>(samples[z * slice + i]));
    spec.position = std::array<double, 3>{0, 0, double(z)};
    spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
    const std::string path = directory + "/s" + std::to_string(1000 + z) + ".dcm";
    write_dicom(path + ".native", spec);
    EXPECT_TRUE(recode(path + ".native", path, syntax_of(z))) << path;
    std::filesystem::remove(path + ".native");
  }
}

}  // namespace mvox::test
