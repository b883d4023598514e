#pragma once
// Which file a path or a descriptor really is: device and inode, after every symbolic link is
// followed. Two names with one identity are one file, whatever their spelling ("vol.raw",
// "./vol.raw", a symbolic or hard link to it, /dev/stdin when the shell redirected it), which is
// what the checks that keep an output from replacing an input (output_targets.h) compare.
#include <cstdint>
#include <optional>
#include <string>

namespace mvox {

struct FileIdentity {
  std::uint64_t device = 0;
  std::uint64_t inode = 0;
  bool character_device = false;  // /dev/null, a terminal: writing there replaces nothing
  bool operator==(const FileIdentity& other) const {
    return device == other.device && inode == other.inode;
  }
  bool operator!=(const FileIdentity& other) const { return !(*this == other); }
};

// The file `path` names, links followed (stat(2)); nothing when it does not exist or cannot be
// reached. "-" is not a path: ask identity_of_descriptor(1) for standard output.
std::optional<FileIdentity> identity_of_path(const std::string& path);

// The file open on descriptor `fd` (fstat(2)); nothing when the descriptor is closed.
std::optional<FileIdentity> identity_of_descriptor(int fd);

}  // namespace mvox
