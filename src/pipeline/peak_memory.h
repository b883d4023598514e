#pragma once
// Process memory, for --stats and the benchmarks. A job's own memory is the peak minus the
// resident size when it started: the shared libraries OpenCV pulls in (GDAL, HDF5, ...) are
// about 48 MiB of resident pages before any work, the same for every scan.
#include <cstdint>

namespace mvox {

// Peak resident set size of this process so far, in bytes (0 where the OS does not tell).
std::uint64_t peak_resident_bytes();

// Resident set size now, in bytes (0 where the OS does not tell).
std::uint64_t current_resident_bytes();

}  // namespace mvox
