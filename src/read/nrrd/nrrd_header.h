#pragma once
// The NRRD header (teem's "nearly raw raster data", format versions NRRD0001 to NRRD0005), parsed
// from its text into what mvox needs to stream the samples. A pure function, separate from the
// reader (nrrd_file.h), so that it can be fuzzed.
#include <cstdint>
#include <string>
#include <string_view>

#include "read/stored_volume.h"

namespace mvox {

struct NrrdHeader {
  // sizes, type, endian, encoding; geometry from "space directions" (spacing = each vector's
  // length, axes = its unit vector) or "spacings", and "space origin".
  StoredVolume volume;
  // "data file:" as written (relative to the header's directory unless absolute); empty when
  // the data follow the header in the same file.
  std::string data_file;
  // Offset of the first byte after the header: after the blank line that ends it, or the end
  // of `text` when no blank line came.
  std::uint64_t header_bytes = 0;
  bool ended_by_blank_line = false;
  std::uint64_t line_skip = 0;  // lines of the data file skipped first (before decompression)
  // Bytes skipped after the lines: in the file for raw data, in the decompressed stream for
  // gzip data (teem's rule). -1 (raw only): the data are the last bytes of the file.
  std::int64_t byte_skip = 0;
};

// Parses the header at the start of `text`, which may go on past the header (attached data):
// lines up to the first blank line, or all of `text`. Fields are matched case-insensitively;
// comments (#) and "key:=value" lines are skipped. Accepted:
//   type       uchar, signed char, short, ushort, float, in all of teem's spellings (uint8,
//              unsigned char, int16_t, ...); signed char is widened to int16. Other types
//              (int, uint, long long, double, block) are refused by name.
//   dimension  3, or 2 for a single slice (depth 1)
//   encoding   raw, gzip (gz)
// Required: the magic line, type, dimension, sizes, encoding, and endian for samples wider
// than a byte. Refused by name: unknown fields, a field given twice, unsupported encodings,
// per-axis fields with the wrong count, non-scalar axis kinds (RGB-color, vector, ...), both
// spacings and space directions, zero-length directions, data file lists and patterns, sizes
// whose volume overflows a signed 64-bit byte count, and attached data without a blank line.
// Throws mvox::Error(file_name, "line N: PROBLEM") (or without a line for a missing field).
NrrdHeader parse_nrrd_header(std::string_view text, const std::string& file_name);

}  // namespace mvox
