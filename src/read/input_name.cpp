#include "read/input_name.h"

#include <optional>

#include "write/standard_descriptors.h"

namespace mvox {

std::string input_name(const std::string& path) {
  const std::optional<int> fd = descriptor_named_by(path);
  return fd == 0 ? descriptor_name(0) : path;
}

}  // namespace mvox
