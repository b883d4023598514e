#pragma once
// Opens a MetaImage volume: a .mhd header naming its data file, or a .mha file whose data
// follow the header (ElementDataFile = LOCAL).
#include <memory>
#include <string>

#include "read/stored_volume_source.h"

namespace mvox {

// Reads and parses the header (parse_metaimage_header; at most its first 1 MiB is read as
// text), finds the data (after the header for LOCAL, else ElementDataFile relative to the
// header's directory), applies HeaderSize (bytes skipped first; -1: the data are the file's
// last bytes), and returns a StoredVolumeSource over it. Throws mvox::Error naming the header
// for header problems and a missing data file, and naming the data file when it is too short
// or corrupt.
std::unique_ptr<StoredVolumeSource> open_metaimage_volume(const std::string& path);

struct InputFormat;

// The input-format row (read/input_format.h) of MetaImage volumes: one .mhd or .mha file, which
// takes no --raw.
const InputFormat& metaimage_volume_format();

}  // namespace mvox
