#include "write/file_identity.h"

#include <sys/stat.h>

namespace mvox {
namespace {

FileIdentity identity_of(const struct stat& status) {
  FileIdentity identity;
  identity.device = static_cast<std::uint64_t>(status.st_dev);
  identity.inode = static_cast<std::uint64_t>(status.st_ino);
  identity.character_device = S_ISCHR(status.st_mode);
  return identity;
}

}  // namespace

std::optional<FileIdentity> identity_of_path(const std::string& path) {
  struct stat status {};
  if (path.empty() || ::stat(path.c_str(), &status) != 0) return std::nullopt;
  return identity_of(status);
}

std::optional<FileIdentity> identity_of_descriptor(int fd) {
  struct stat status {};
  if (::fstat(fd, &status) != 0) return std::nullopt;
  return identity_of(status);
}

}  // namespace mvox
