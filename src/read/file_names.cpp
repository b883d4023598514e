#include "read/file_names.h"

#include <cctype>

namespace mvox {

std::string file_name_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string lowercase_extension(const std::string& path) {
  const std::string name = file_name_of(path);
  if (name == "." || name == "..") return "";
  const std::size_t dot = name.rfind('.');
  if (dot == std::string::npos || dot == 0) return "";
  std::string extension = name.substr(dot);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

}  // namespace mvox
