#include "read/natural_sort.h"

#include <algorithm>
#include <cstddef>

namespace mvox {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Compares the digit runs a[ia, a_end) and b[ib, b_end) by value: -1, 0 or 1.
int compare_digit_runs(const std::string& a, std::size_t ia, std::size_t a_end,
                       const std::string& b, std::size_t ib, std::size_t b_end) {
  // Leading zeros carry no value; after skipping them the longer run is the larger number.
  while (ia < a_end && a[ia] == '0') ++ia;
  while (ib < b_end && b[ib] == '0') ++ib;
  const std::size_t a_len = a_end - ia;
  const std::size_t b_len = b_end - ib;
  if (a_len != b_len) return a_len < b_len ? -1 : 1;
  for (; ia < a_end; ++ia, ++ib) {
    if (a[ia] != b[ib]) return a[ia] < b[ib] ? -1 : 1;
  }
  return 0;
}

// Natural comparison without the final tie-break: -1, 0 or 1.
int natural_compare(const std::string& a, const std::string& b) {
  // Names of one stack share a long prefix ("scans/head/slice_0"): skip it, back to the start of
  // the digit run it ends in, since a run compares by its whole value.
  std::size_t common =
      std::mismatch(a.begin(),
                    a.begin() + static_cast<std::ptrdiff_t>(std::min(a.size(), b.size())),
                    b.begin())
          .first -
      a.begin();
  while (common > 0 && is_digit(a[common - 1])) --common;
  std::size_t ia = common;
  std::size_t ib = common;
  while (ia < a.size() && ib < b.size()) {
    if (is_digit(a[ia]) && is_digit(b[ib])) {
      std::size_t a_end = ia;
      std::size_t b_end = ib;
      while (a_end < a.size() && is_digit(a[a_end])) ++a_end;
      while (b_end < b.size() && is_digit(b[b_end])) ++b_end;
      const int order = compare_digit_runs(a, ia, a_end, b, ib, b_end);
      if (order != 0) return order;
      ia = a_end;
      ib = b_end;
      continue;
    }
    // A digit against a non-digit: the digits '0'..'9' are contiguous in ASCII, so comparing the
    // two bytes places every number at the same spot among the other characters, which keeps
    // the order transitive.
    const auto ca = static_cast<unsigned char>(a[ia]);
    const auto cb = static_cast<unsigned char>(b[ib]);
    if (ca != cb) return ca < cb ? -1 : 1;
    ++ia;
    ++ib;
  }
  if (ia < a.size()) return 1;  // b is a prefix of a
  if (ib < b.size()) return -1;
  return 0;
}

}  // namespace

bool natural_less(const std::string& a, const std::string& b) {
  const int order = natural_compare(a, b);
  if (order != 0) return order < 0;
  return a < b;
}

void natural_sort(std::vector<std::string>& names) {
  std::sort(names.begin(), names.end(), natural_less);
}

}  // namespace mvox
