#pragma once
// Orders file names the way people number slices: "slice2" before "slice10", "CThead.9" before
// "CThead.10". Scanners and scripts rarely zero-pad, so plain string order scrambles the volume.
#include <string>
#include <vector>

namespace mvox {

// Strict weak order on byte strings. Runs of ASCII digits compare by numeric value, however long
// (compared as digit strings, never converted, so 40-digit runs cannot overflow); other bytes
// compare as unsigned chars. Names equal by that rule ("a01", "a1") fall back to plain byte
// order, so the result never depends on the input order.
bool natural_less(const std::string& a, const std::string& b);

// Sorts `names` in place by natural_less.
void natural_sort(std::vector<std::string>& names);

}  // namespace mvox
