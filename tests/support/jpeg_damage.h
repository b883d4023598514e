#pragma once
// Test support: the damage libjpeg only warns about, done to a JPEG file's bytes. libjpeg
// decodes these with "Corrupt JPEG data: ..." on standard error and grey where data are missing,
// so they test that mvox's strict decoder refuses them (jpeg_slice_decoder.h).
#include <cstddef>
#include <vector>

namespace mvox::test {

// Where the entropy-coded data of the first scan of `jpeg` start (just after its SOS segment)
// and end (at the marker that follows them, other than a restart marker), or {0, 0} when there
// is no scan.
struct ScanData {
  std::size_t begin = 0;
  std::size_t end = 0;
};
ScanData first_scan_data(const std::vector<unsigned char>& jpeg);

// `jpeg` cut `kept` bytes into its first scan's data and closed with an end-of-image marker
// (FF D9), so that the file still ends like a whole JPEG. A stuffed FF at the cut is dropped.
std::vector<unsigned char> cut_in_scan(const std::vector<unsigned char>& jpeg, std::size_t kept);

// `jpeg`, written with a restart interval, with its second restart marker of the first scan
// renumbered (RSTn becomes RST(n+3 mod 8)), as a damaged or spliced file would have it.
std::vector<unsigned char> renumber_restart_marker(const std::vector<unsigned char>& jpeg);

// `jpeg` with two junk restart markers (FF D5 FF D2) inserted at byte `at` of its first scan's
// data (moved back when it falls just after an FF).
std::vector<unsigned char> insert_restart_markers(const std::vector<unsigned char>& jpeg,
                                                  std::size_t at);

}  // namespace mvox::test
