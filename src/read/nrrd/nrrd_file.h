#pragma once
// Opens a NRRD volume: a .nrrd file (header, blank line, data) or a detached .nhdr header
// naming its data file.
#include <memory>
#include <string>

#include "read/stored_volume_source.h"

namespace mvox {

// Reads and parses the header (parse_nrrd_header; at most its first 1 MiB is read as text),
// finds the data (the header's own file after the blank line, or "data file:" relative to the
// header's directory), applies line skip and byte skip, and returns a StoredVolumeSource over
// it. Throws mvox::Error naming the header for header problems and a missing data file, and
// naming the data file when it is too short or corrupt.
std::unique_ptr<StoredVolumeSource> open_nrrd_volume(const std::string& path);

struct InputFormat;

// The input-format row (read/input_format.h) of NRRD volumes: one .nrrd or .nhdr file, which
// takes no --raw.
const InputFormat& nrrd_volume_format();

}  // namespace mvox
