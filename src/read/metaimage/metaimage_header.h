#pragma once
// The MetaImage header (ITK/VTK's .mhd and .mha: "Key = Value" lines ending with
// ElementDataFile), parsed from its text into what mvox needs to stream the samples. A pure
// function, separate from the reader (metaimage_file.h), so that it can be fuzzed.
#include <cstdint>
#include <string>
#include <string_view>

#include "read/stored_volume.h"

namespace mvox {

struct MetaImageHeader {
  // DimSize, ElementType, byte order, CompressedData; geometry from ElementSpacing (or
  // ElementSize when there is no ElementSpacing, as MetaIO does), Offset / Origin / Position
  // and TransformMatrix / Rotation / Orientation (its numbers 3i .. 3i+2 are the world
  // direction of voxel axis i, as ITK reads them).
  StoredVolume volume;
  // ElementDataFile = LOCAL: the data follow the header in the same file (.mha).
  bool data_local = false;
  // Otherwise the data file as written (relative to the header's directory unless absolute).
  std::string data_file;
  // Offset just past the ElementDataFile line, where LOCAL data start.
  std::uint64_t header_bytes = 0;
  // HeaderSize: bytes skipped at the start of the data (for LOCAL data: after the header);
  // -1: the data are the last bytes of the data file (uncompressed data only).
  std::int64_t header_size = 0;
  // CompressedDataSize: bytes of compressed data; 0 when not given.
  std::uint64_t compressed_bytes = 0;
};

// Parses `text`, which may go on past the header (.mha with LOCAL data): lines up to and
// including ElementDataFile. Keys are matched case-insensitively; keys mvox does not use
// (Comment, AnatomicalOrientation, ElementMin, ...) are ignored, as MetaIO keeps them.
// Accepted: NDims 3 (or 2, one slice); ElementType MET_UCHAR, MET_CHAR (widened to 16-bit),
// MET_USHORT, MET_SHORT, MET_FLOAT; ElementNumberOfChannels 1; BinaryData True;
// ElementByteOrderMSB / BinaryDataByteOrderMSB (absent: little-endian, what every common
// machine writes). Required: NDims, DimSize, ElementType, ElementDataFile.
// Refused by name: other element types, several channels, ASCII data, an ObjectType that is
// not Image, a key given twice, values of the wrong count or form, data file lists and
// patterns, HeaderSize -1 with compressed data, sizes whose volume overflows a signed 64-bit
// byte count, and a header without ElementDataFile.
// Throws mvox::Error(file_name, "line N: PROBLEM") (or without a line for a missing key).
MetaImageHeader parse_metaimage_header(std::string_view text, const std::string& file_name);

}  // namespace mvox
