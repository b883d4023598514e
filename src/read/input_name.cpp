#include "read/input_name.h"

#include <optional>

#include "write/standard_descriptors.h"

namespace mvox {

std::string input_name(const std::string& path) {
  const std::optional<int> fd = descriptor_named_by(path);
  return fd ? descriptor_name(*fd) : path;
}

}  // namespace mvox
