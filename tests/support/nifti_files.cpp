#include "nifti_files.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "deflate.h"

namespace mvox::test {
namespace {

class HeaderBytes {
 public:
  HeaderBytes(std::size_t size, bool swap) : bytes_(size, 0), swap_(swap) {}
  template <class T>
  void put(std::size_t offset, T value) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (swap_)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    std::memcpy(bytes_.data() + offset, raw, sizeof(T));
  }
  void text(std::size_t offset, const std::string& value) {
    std::memcpy(bytes_.data() + offset, value.data(), value.size());
  }
  std::vector<unsigned char> bytes_;

 private:
  bool swap_;
};

bool host_is_little() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << "cannot write " << path;
}

}  // namespace

std::vector<unsigned char> nifti_header_bytes(const NiftiFile& f) {
  const bool swap = f.big_endian == host_is_little();
  const bool two = f.version == 2;
  HeaderBytes h(two ? 540 : 348, swap);
  h.put<std::int32_t>(0, two ? 540 : 348);
  std::string magic = f.magic;
  if (magic.empty())
    magic = two ? std::string(f.pair ? "ni2" : "n+2") + std::string("\0\r\n\032\n", 5)
                : std::string(f.pair ? "ni1" : "n+1") + std::string(1, '\0');
  const std::int64_t vox_offset = f.vox_offset >= 0 ? f.vox_offset : f.pair ? 0 : (two ? 544 : 352);
  if (two) {
    h.text(4, magic);
    h.put<std::int16_t>(12, f.datatype);
    h.put<std::int16_t>(14, f.bitpix);
    for (int i = 0; i < 8; ++i) h.put<std::int64_t>(16 + 8 * i, f.dim[i]);
    for (int i = 0; i < 8; ++i) h.put<double>(104 + 8 * i, f.pixdim[i]);
    h.put<std::int64_t>(168, vox_offset);
    h.put<double>(176, f.scl_slope);
    h.put<double>(184, f.scl_inter);
    h.put<std::int32_t>(344, f.qform_code);
    h.put<std::int32_t>(348, f.sform_code);
    for (int i = 0; i < 6; ++i) h.put<double>(352 + 8 * i, f.quatern[i]);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) h.put<double>(400 + 32 * r + 8 * c, f.srow[r][c]);
    h.put<std::int32_t>(500, f.xyzt_units);
  } else {
    h.text(344, magic);
    for (int i = 0; i < 8; ++i) h.put<std::int16_t>(40 + 2 * i, static_cast<std::int16_t>(f.dim[i]));
    h.put<std::int16_t>(70, f.datatype);
    h.put<std::int16_t>(72, f.bitpix);
    for (int i = 0; i < 8; ++i) h.put<float>(76 + 4 * i, static_cast<float>(f.pixdim[i]));
    h.put<float>(108, static_cast<float>(vox_offset));
    h.put<float>(112, static_cast<float>(f.scl_slope));
    h.put<float>(116, static_cast<float>(f.scl_inter));
    h.bytes_[123] = static_cast<unsigned char>(f.xyzt_units);
    h.put<std::int16_t>(252, static_cast<std::int16_t>(f.qform_code));
    h.put<std::int16_t>(254, static_cast<std::int16_t>(f.sform_code));
    for (int i = 0; i < 6; ++i) h.put<float>(256 + 4 * i, static_cast<float>(f.quatern[i]));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) h.put<float>(280 + 16 * r + 4 * c, static_cast<float>(f.srow[r][c]));
  }
  return h.bytes_;
}

void write_nifti(const std::string& path, const NiftiFile& f) {
  std::vector<unsigned char> samples = f.samples;
  const std::size_t sample_size = f.bitpix >= 8 ? static_cast<std::size_t>(f.bitpix / 8) : 1;
  if (f.big_endian == host_is_little() && sample_size > 1)
    for (std::size_t i = 0; i + sample_size <= samples.size(); i += sample_size)
      for (std::size_t b = 0; b < sample_size / 2; ++b)
        std::swap(samples[i + b], samples[i + sample_size - 1 - b]);
  std::vector<unsigned char> header = nifti_header_bytes(f);
  const std::int64_t vox_offset =
      f.vox_offset >= 0 ? f.vox_offset : f.pair ? 0 : static_cast<std::int64_t>(header.size()) + 4;
  if (f.pair) {
    write_bytes(path, header);
    std::vector<unsigned char> image(static_cast<std::size_t>(vox_offset), 0);
    image.insert(image.end(), samples.begin(), samples.end());
    const std::string stem = path.substr(0, path.size() - 4);
    if (f.gzip)
      write_bytes(stem + ".img.gz", deflate_bytes(image, true));
    else
      write_bytes(stem + ".img", image);
    return;
  }
  std::vector<unsigned char> whole = header;
  if (static_cast<std::int64_t>(whole.size()) < vox_offset)
    whole.resize(static_cast<std::size_t>(vox_offset), 0);  // the 4 extension bytes (none)
  whole.insert(whole.end(), samples.begin(), samples.end());
  write_bytes(path, f.gzip ? deflate_bytes(whole, true) : whole);
}

}  // namespace mvox::test
