#include "read/nifti/nifti_header.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>

#include "error.h"

namespace mvox {
namespace {

// Field offsets: the published NIfTI-1 (nifti1.h) and NIfTI-2 (nifti2.h) layouts.
struct Layout {
  std::size_t dim, datatype, bitpix, pixdim, vox_offset, scl_slope, scl_inter;
  std::size_t qform_code, sform_code, quatern, srow, xyzt_units;
  bool wide;  // NIfTI-2: 64-bit integers and doubles where NIfTI-1 has 16-bit and float
};
constexpr Layout kNifti1 = {40, 70, 72, 76, 108, 112, 116, 252, 254, 256, 280, 123, false};
constexpr Layout kNifti2 = {16, 12, 14, 104, 168, 176, 184, 344, 348, 352, 400, 500, true};

// Reads the header's fields in its byte order.
class Fields {
 public:
  Fields(const unsigned char* bytes, bool swap) : bytes_(bytes), swap_(swap) {}

  template <class T>
  T get(std::size_t offset) const {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, bytes_ + offset, sizeof(T));
    if (swap_)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }
  // An integer field that is 16 bits in NIfTI-1 and 64 in NIfTI-2 (dim), or 32 (codes).
  std::int64_t integer(const Layout& layout, std::size_t offset, int index = 0) const {
    return layout.wide ? get<std::int64_t>(offset + 8 * index)
                       : get<std::int16_t>(offset + 2 * index);
  }
  // A float field that is a double in NIfTI-2.
  double real(const Layout& layout, std::size_t offset, int index = 0) const {
    return layout.wide ? get<double>(offset + 8 * index)
                       : static_cast<double>(get<float>(offset + 4 * index));
  }

 private:
  const unsigned char* bytes_;
  bool swap_;
};

struct DataType {
  std::int64_t code;
  const char* name;
  int bits;
  bool read;
  StoredSample stored;
};
constexpr DataType kDataTypes[] = {
    {2, "uint8", 8, true, StoredSample::u8},        {4, "int16", 16, true, StoredSample::i16},
    {8, "int32", 32, true, StoredSample::i32},      {16, "float32", 32, true, StoredSample::f32},
    {64, "float64", 64, true, StoredSample::f64},   {256, "int8", 8, true, StoredSample::i8},
    {512, "uint16", 16, true, StoredSample::u16},   {768, "uint32", 32, true, StoredSample::u32},
    {1, "binary", 1, false, StoredSample::u8},      {32, "complex64", 64, false, StoredSample::u8},
    {128, "RGB24", 24, false, StoredSample::u8},    {1024, "int64", 64, false, StoredSample::u8},
    {1280, "uint64", 64, false, StoredSample::u8},  {1536, "float128", 128, false, StoredSample::u8},
    {1792, "complex128", 128, false, StoredSample::u8},
    {2048, "complex256", 256, false, StoredSample::u8},
    {2304, "RGBA32", 32, false, StoredSample::u8},
};

const char* kTypesRead = "uint8, int8, uint16, int16, uint32, int32, float32 and float64";

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

// The columns of the voxel-to-world map as mvox's spacing and axes, and its offset as the
// origin. A column of zero length is taken from the other two only for a single slice.
void set_geometry(VolumeInfo& info, const double columns[3][3], const double origin[3],
                  const char* what, const std::string& path) {
  for (int axis = 0; axis < 3; ++axis) {
    if (set_axis_from_vector(info, axis, columns[axis])) continue;
    const bool flat_third = axis == 2 && info.depth == 1;
    if (flat_third && complete_third_axis(info)) continue;
    throw Error(path, std::string(what) + " gives voxel axis " + "ijk"[axis] +
                          " no direction (a zero, subnormal or non-finite column)");
  }
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(origin[i])) throw Error(path, std::string(what) + " offset is not finite");
    info.origin[i] = origin[i];
  }
}

}  // namespace

std::size_t nifti_header_size(const unsigned char* bytes) {
  std::int32_t size;
  std::memcpy(&size, bytes, 4);
  if (size == 348 || size == 540) return static_cast<std::size_t>(size);
  const std::uint32_t swapped = __builtin_bswap32(static_cast<std::uint32_t>(size));
  if (swapped == 348 || swapped == 540) return swapped;
  return 0;
}

NiftiHeader parse_nifti_header(const unsigned char* bytes, std::size_t size,
                               const std::string& path) {
  if (size < 4) throw Error(path, "file is " + std::to_string(size) + " bytes, too short for a NIfTI header");
  const std::size_t header_size = nifti_header_size(bytes);
  if (header_size == 0)
    throw Error(path, "not a NIfTI file: its first four bytes (sizeof_hdr) are neither 348 "
                      "(NIfTI-1) nor 540 (NIfTI-2)");
  if (size < header_size)
    throw Error(path, "file ends after " + std::to_string(size) + " bytes, inside its " +
                          std::to_string(header_size) + "-byte NIfTI header");
  std::int32_t native_size;
  std::memcpy(&native_size, bytes, 4);
  const bool swap = native_size != static_cast<std::int32_t>(header_size);
  const Fields fields(bytes, swap);

  NiftiHeader header;
  header.header_bytes = header_size;
  header.version = header_size == 540 ? 2 : 1;
  const Layout& layout = header.version == 2 ? kNifti2 : kNifti1;
  const bool little_host = [] {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 1;
  }();
  header.volume.byte_order = (little_host != swap) ? ByteOrder::little : ByteOrder::big;

  // Magic: "n+1\0" (one file) or "ni1\0" (a .hdr with its .img); NIfTI-2 adds "\r\n\032\n".
  if (header.version == 1) {
    const unsigned char* magic = bytes + 344;
    if (std::memcmp(magic, "n+1\0", 4) == 0) {
      header.single_file = true;
    } else if (std::memcmp(magic, "ni1\0", 4) == 0) {
      header.single_file = false;
    } else {
      throw Error(path, "no NIfTI-1 magic (\"n+1\" or \"ni1\" at byte 344): an Analyze 7.5 "
                        "header, or not NIfTI; mvox reads NIfTI-1 and NIfTI-2");
    }
  } else {
    const unsigned char* magic = bytes + 4;
    if (std::memcmp(magic, "n+2\0\r\n\032\n", 8) == 0) {
      header.single_file = true;
    } else if (std::memcmp(magic, "ni2\0\r\n\032\n", 8) == 0) {
      header.single_file = false;
    } else {
      throw Error(path, "no NIfTI-2 magic (\"n+2\" or \"ni2\" and \\r\\n\\032\\n at byte 4)");
    }
  }

  // Dimensions: dim[0] of them, sizes >= 1; mvox takes one 3-D volume.
  const std::int64_t dimensions = fields.integer(layout, layout.dim, 0);
  if (dimensions < 1 || dimensions > 7)
    throw Error(path, "dim[0] is " + std::to_string(dimensions) + ", expected 1 to 7 dimensions");
  std::int64_t sizes[8] = {0, 1, 1, 1, 1, 1, 1, 1};
  for (int d = 1; d <= dimensions; ++d) {
    sizes[d] = fields.integer(layout, layout.dim, d);
    if (sizes[d] < 1)
      throw Error(path, "dim[" + std::to_string(d) + "] is " + std::to_string(sizes[d]) +
                            ", expected a size of at least 1");
  }
  std::int64_t volumes = 1;
  for (int d = 4; d <= dimensions; ++d) {
    if (sizes[d] > 1 && volumes > (std::int64_t{1} << 40) / sizes[d]) volumes = std::int64_t{1} << 40;
    else volumes *= sizes[d];
  }
  if (volumes > 1)
    throw Error(path, "a " + std::to_string(dimensions) + "-D image of " + std::to_string(volumes) +
                          " volumes of " + std::to_string(sizes[1]) + "x" +
                          std::to_string(sizes[2]) + "x" + std::to_string(sizes[3]) +
                          " voxels; mvox extracts one 3-D volume: split it first (e.g. fslsplit)");

  // Samples.
  const std::int64_t code = fields.get<std::int16_t>(layout.datatype);
  const std::int64_t bitpix = fields.get<std::int16_t>(layout.bitpix);
  const DataType* type = nullptr;
  for (const DataType& candidate : kDataTypes)
    if (candidate.code == code) type = &candidate;
  if (!type)
    throw Error(path, "datatype " + std::to_string(code) + " is not a NIfTI data type; mvox reads " +
                          kTypesRead);
  if (!type->read)
    throw Error(path, std::string("datatype ") + type->name + " (" + std::to_string(code) +
                          "): mvox reads " + kTypesRead + " samples");
  if (bitpix != type->bits)
    throw Error(path, "bitpix is " + std::to_string(bitpix) + ", but datatype " + type->name +
                          " has " + std::to_string(type->bits) + " bits");
  header.volume.stored = type->stored;
  if (!volume_size_fits(static_cast<std::uint64_t>(sizes[1]), static_cast<std::uint64_t>(sizes[2]),
                        static_cast<std::uint64_t>(sizes[3]), stored_sample_bytes(type->stored)))
    throw Error(path, std::to_string(sizes[1]) + "x" + std::to_string(sizes[2]) + "x" +
                          std::to_string(sizes[3]) + " " + type->name +
                          " voxels: too large a volume to address");
  VolumeInfo& info = header.volume.info;
  info.width = static_cast<std::uint32_t>(sizes[1]);
  info.height = static_cast<std::uint32_t>(sizes[2]);
  info.depth = static_cast<std::uint32_t>(sizes[3]);

  // Scaling: a slope of 0 (or NaN, as some writers leave it) means none.
  const double slope = fields.real(layout, layout.scl_slope);
  const double intercept = fields.real(layout, layout.scl_inter);
  if (slope != 0 && !std::isnan(slope)) {
    if (!std::isfinite(slope) || !std::isfinite(intercept))
      throw Error(path, "scl_slope " + number(slope) + " and scl_inter " + number(intercept) +
                            ": the scaling must be finite");
    header.volume.scale_slope = slope;
    header.volume.scale_intercept = intercept;
  }
  info.type = scaled_engine_type(header.volume);

  // Where the samples start.
  // An int64 in NIfTI-2, a float in NIfTI-1 (exact for whole numbers up to 2^24).
  const double offset = layout.wide
                            ? static_cast<double>(fields.get<std::int64_t>(layout.vox_offset))
                            : static_cast<double>(fields.get<float>(layout.vox_offset));
  const double lowest = header.single_file ? static_cast<double>(header_size) : 0.0;
  if (!(offset >= lowest) || offset != std::floor(offset) || offset > 9.0e15)
    throw Error(path, "vox_offset is " + number(offset) +
                          (header.single_file
                               ? ", expected a whole number of bytes at or after the " +
                                     std::to_string(header_size) + "-byte header"
                               : std::string(", expected a whole number of bytes")));
  header.vox_offset = static_cast<std::uint64_t>(offset);

  // Units: millimetres, the unit of NIfTI's world; metres and micrometres are converted.
  const int units = (layout.wide ? fields.get<std::int32_t>(layout.xyzt_units)
                                 : static_cast<int>(bytes[layout.xyzt_units])) &
                    0x07;
  const double to_mm = units == 1 ? 1000.0 : units == 3 ? 0.001 : 1.0;

  // Voxel sizes: pixdim[1..3], used by the qform and without transform. A size-1 axis may have
  // 0 (nothing to measure); elsewhere they must be finite and nonzero.
  double voxel[3];
  for (int axis = 0; axis < 3; ++axis) {
    const double value = std::fabs(fields.real(layout, layout.pixdim, axis + 1));
    const std::int64_t extent = sizes[axis + 1];
    if (value == 0 && extent == 1) {
      voxel[axis] = 1;
    } else if (!(value > 0) || !std::isfinite(value)) {
      throw Error(path, "pixdim[" + std::to_string(axis + 1) + "] is " +
                            number(fields.real(layout, layout.pixdim, axis + 1)) +
                            ": voxel sizes must be finite and nonzero");
    } else {
      voxel[axis] = value;
    }
  }

  const std::int64_t sform_code = layout.wide ? fields.get<std::int32_t>(layout.sform_code)
                                              : fields.get<std::int16_t>(layout.sform_code);
  const std::int64_t qform_code = layout.wide ? fields.get<std::int32_t>(layout.qform_code)
                                              : fields.get<std::int16_t>(layout.qform_code);
  double columns[3][3] = {{voxel[0], 0, 0}, {0, voxel[1], 0}, {0, 0, voxel[2]}};
  double origin[3] = {0, 0, 0};
  if (sform_code > 0) {
    // srow_x, srow_y, srow_z: the rows of the 3x4 affine.
    for (int row = 0; row < 3; ++row) {
      for (int column = 0; column < 3; ++column)
        columns[column][row] = fields.real(layout, layout.srow, row * 4 + column);
      origin[row] = fields.real(layout, layout.srow, row * 4 + 3);
    }
    header.placed_by = "sform";
  } else if (qform_code > 0) {
    // The rotation from the quaternion (b, c, d), a = sqrt(1 - b^2 - c^2 - d^2), as nifti1.h
    // defines it; qfac (pixdim[0], -1 or 1) flips the k axis.
    double b = fields.real(layout, layout.quatern, 0), c = fields.real(layout, layout.quatern, 1);
    double d = fields.real(layout, layout.quatern, 2);
    if (!std::isfinite(b) || !std::isfinite(c) || !std::isfinite(d))
      throw Error(path, "the qform's quaternion is not finite");
    double a = 1.0 - (b * b + c * c + d * d);
    if (a < 1e-7) {
      // Rounding put (b, c, d) on or past the unit sphere: a 180-degree turn.
      const double length = std::sqrt(b * b + c * c + d * d);
      b /= length;
      c /= length;
      d /= length;
      a = 0;
    } else {
      a = std::sqrt(a);
    }
    const double rotation[3][3] = {
        {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
        {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
        {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
    const double qfac = fields.real(layout, layout.pixdim, 0) < 0 ? -1.0 : 1.0;
    for (int column = 0; column < 3; ++column) {
      const double size = voxel[column] * (column == 2 ? qfac : 1.0);
      for (int row = 0; row < 3; ++row) columns[column][row] = rotation[row][column] * size;
    }
    for (int i = 0; i < 3; ++i) origin[i] = fields.real(layout, layout.quatern, 3 + i);
    header.placed_by = "qform";
  }
  for (auto& column : columns)
    for (double& value : column) value *= to_mm;
  for (double& value : origin) value *= to_mm;
  set_geometry(info, columns, origin, header.placed_by, path);
  return header;
}

}  // namespace mvox
