#pragma once
// Standard input, output and error as files: which of them the user closed, and which paths
// name them (or another open descriptor) rather than a file to create.
//
// Why it matters: a process started with standard output closed (`mvox ... -o - >&-`) gets
// descriptor 1 back from its next open(), so a scratch file would become "standard output" and
// the mesh would be written into it and lost, with exit 0. And /dev/stdout, /dev/fd/N and
// /proc/self/fd/N are links to whatever the shell redirected: writing through a temporary
// and a rename would replace the link itself (as root, even /dev/stdout), leaving the user's
// file empty. Such paths are written through their descriptor instead.
#include <optional>
#include <string>

namespace mvox {

// Call first in main, before any file is opened: puts /dev/null on each of descriptors 0, 1
// and 2 that is closed, so that no file mvox opens later takes their numbers, and remembers
// which were closed. Idempotent.
void secure_standard_descriptors();

// True when descriptor `fd` (0, 1 or 2) was closed when secure_standard_descriptors() ran.
bool standard_descriptor_was_closed(int fd);

// The descriptor `path` names without anything to open or create, or nothing: "/dev/stdin",
// "/dev/stdout", "/dev/stderr" (0, 1, 2), "/dev/fd/N", "/proc/self/fd/N" and
// "/proc/PID/fd/N" for this process's PID (N), however spelled (relative, with "." or ".."
// parts). "-" is not a path and gives nothing: the caller decides what it means.
std::optional<int> descriptor_named_by(const std::string& path);

// "standard output" for 1, "standard input" for 0, "standard error" for 2, "descriptor N"
// otherwise: how messages name a descriptor.
std::string descriptor_name(int fd);

}  // namespace mvox
