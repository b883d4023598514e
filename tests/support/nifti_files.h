#pragma once
// Test support: NIfTI-1 and NIfTI-2 files written byte by byte from the published header
// layouts, in either byte order, as .nii, .nii.gz or a .hdr/.img pair, so that the reader is
// checked against files whose every field the test chose (including wrong ones).
#include <cstdint>
#include <string>
#include <vector>

namespace mvox::test {

struct NiftiFile {
  int version = 1;           // 1 (348-byte header) or 2 (540)
  bool big_endian = false;
  bool gzip = false;         // .nii.gz (or .img.gz for a pair)
  bool pair = false;         // a .hdr with the samples in a .img
  std::int64_t dim[8] = {3, 1, 1, 1, 1, 1, 1, 1};
  std::int16_t datatype = 2;  // uint8
  std::int16_t bitpix = 8;
  double pixdim[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  double scl_slope = 0, scl_inter = 0;
  int qform_code = 0, sform_code = 0;
  double quatern[6] = {0, 0, 0, 0, 0, 0};  // b, c, d, qoffset_x, y, z
  double srow[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  int xyzt_units = 2;  // millimetres
  std::int64_t vox_offset = -1;  // -1: right after the header and its 4 extension bytes (0 for a pair)
  std::string magic;             // empty: the right one for version and pair
  // The samples as stored, in the host's byte order (swapped when big_endian and sized by
  // bitpix); written after vox_offset.
  std::vector<unsigned char> samples;
};

// The header's bytes (348 or 540).
std::vector<unsigned char> nifti_header_bytes(const NiftiFile& file);

// Writes `file` to `path` (ending in .nii, .nii.gz or .hdr; a pair's .img beside it). Returns
// the path written; a failure fails the test.
void write_nifti(const std::string& path, const NiftiFile& file);

// The samples of `values` as `T`, bytes in the host's order.
template <class T>
std::vector<unsigned char> sample_bytes_of(const std::vector<T>& values) {
  std::vector<unsigned char> bytes(values.size() * sizeof(T));
  for (std::size_t i = 0; i < values.size(); ++i)
    for (std::size_t b = 0; b < sizeof(T); ++b)
      bytes[i * sizeof(T) + b] = reinterpret_cast<const unsigned char*>(&values[i])[b];
  return bytes;
}

}  // namespace mvox::test
