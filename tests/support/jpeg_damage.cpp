#include "jpeg_damage.h"

#include <gtest/gtest.h>

namespace mvox::test {
namespace {

bool is_restart_marker(unsigned char code) { return code >= 0xd0 && code <= 0xd7; }

}  // namespace

ScanData first_scan_data(const std::vector<unsigned char>& jpeg) {
  // Markers before the scan are segments FF xx with a 2-byte big-endian length.
  std::size_t at = 2;  // after SOI
  while (at + 4 <= jpeg.size() && jpeg[at] == 0xff) {
    const unsigned char code = jpeg[at + 1];
    const std::size_t length = std::size_t{jpeg[at + 2]} << 8 | jpeg[at + 3];
    at += 2 + length;
    if (code != 0xda) continue;
    ScanData scan{at, at};
    // In entropy-coded data an FF is followed by 00 (a stuffed byte) or a restart marker.
    while (scan.end + 1 < jpeg.size() && !(jpeg[scan.end] == 0xff && jpeg[scan.end + 1] != 0 &&
                                           !is_restart_marker(jpeg[scan.end + 1])))
      ++scan.end;
    return scan;
  }
  return {};
}

std::vector<unsigned char> cut_in_scan(const std::vector<unsigned char>& jpeg, std::size_t kept) {
  const ScanData scan = first_scan_data(jpeg);
  EXPECT_LT(kept, scan.end - scan.begin) << "the cut must fall inside the scan";
  std::vector<unsigned char> cut(jpeg.begin(), jpeg.begin() + scan.begin + kept);
  if (cut.back() == 0xff) cut.pop_back();
  cut.push_back(0xff);
  cut.push_back(0xd9);
  return cut;
}

std::vector<unsigned char> renumber_restart_marker(const std::vector<unsigned char>& jpeg) {
  const ScanData scan = first_scan_data(jpeg);
  std::vector<unsigned char> damaged = jpeg;
  int seen = 0;
  for (std::size_t at = scan.begin; at + 1 < scan.end; ++at) {
    if (damaged[at] == 0xff && is_restart_marker(damaged[at + 1]) && ++seen == 2) {
      damaged[at + 1] = static_cast<unsigned char>(0xd0 + (damaged[at + 1] - 0xd0 + 3) % 8);
      return damaged;
    }
  }
  ADD_FAILURE() << "the first scan has fewer than two restart markers";
  return damaged;
}

std::vector<unsigned char> insert_restart_markers(const std::vector<unsigned char>& jpeg,
                                                  std::size_t at) {
  const ScanData scan = first_scan_data(jpeg);
  std::size_t where = scan.begin + at;
  EXPECT_LT(where, scan.end) << "the markers must go inside the scan";
  while (where > scan.begin && jpeg[where - 1] == 0xff) --where;
  std::vector<unsigned char> damaged = jpeg;
  const unsigned char junk[] = {0xff, 0xd5, 0xff, 0xd2};
  damaged.insert(damaged.begin() + static_cast<std::ptrdiff_t>(where), std::begin(junk),
                 std::end(junk));
  return damaged;
}

}  // namespace mvox::test
