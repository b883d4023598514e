#pragma once
// The binary header of a NIfTI-1 (348 bytes) or NIfTI-2 (540 bytes) volume, checked field by
// field: what mvox needs to stream its samples and place the mesh in NIfTI's world.
//
// Geometry. The header maps voxel (i, j, k) to NIfTI's world by the sform when sform_code > 0,
// else by the qform (a rotation given as a quaternion, the voxel sizes and qfac) when
// qform_code > 0, else by the voxel sizes alone (Analyze's "method 1"). mvox's columns, rows and
// slices are i, j and k, so the mesh lands in that world: RAS+, millimetres, +x towards the
// patient's right, +y anterior, +z superior (DICOM's LPS with x and y negated).
#include <cstddef>
#include <cstdint>
#include <string>

#include "read/stored_volume.h"

namespace mvox {

struct NiftiHeader {
  // Sizes, stored and engine sample types, byte order (the header's), scaling, spacing, origin
  // and axes. Compression is the caller's to set (.nii.gz).
  StoredVolume volume;
  int version = 1;             // 1 or 2
  std::size_t header_bytes = 348;  // 348 or 540
  // n+1 / n+2: the samples follow in the same file at vox_offset. ni1 / ni2: they are in a .img
  // file beside the .hdr, from vox_offset (usually 0).
  bool single_file = true;
  std::uint64_t vox_offset = 0;
  // Which transform placed the volume: "sform", "qform" or "voxel sizes".
  const char* placed_by = "voxel sizes";
};

// The smallest prefix of a file that holds either header: parse_nifti_header needs at least
// kNiftiMinBytes to tell the version, and header_bytes of it to parse.
constexpr std::size_t kNiftiMinBytes = 348;
constexpr std::size_t kNifti2Bytes = 540;

// The header's size from its first four bytes (sizeof_hdr, in either byte order): 348, 540, or 0
// when it is neither (not a NIfTI file). `bytes` holds at least 4 bytes.
std::size_t nifti_header_size(const unsigned char* bytes);

// Parses the header at the start of `bytes` (`size` of them: at least the header's size).
// Refuses, with mvox::Error naming `path`: a size that is not NIfTI's, a magic that is not
// n+1/ni1 (n+2/ni2 for NIfTI-2), fewer than 1 or more than 7 dimensions, a size below 1, a
// volume of more than one 3-D volume (4-D and up: split it first), a data type mvox does not
// read or whose bitpix disagrees, complex and RGB data, voxel sizes or transforms that are not
// finite, a zero voxel size, a non-finite scaling, and a vox_offset inside the header.
NiftiHeader parse_nifti_header(const unsigned char* bytes, std::size_t size,
                               const std::string& path);

}  // namespace mvox
