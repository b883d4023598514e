#pragma once
// How messages name an input path: a path that names one of this process's descriptors rather
// than a file (/dev/stdin, /dev/fd/0, /proc/self/fd/0; "-" on the command line becomes
// /dev/stdin) is named as the descriptor, "standard input", and any other path as given. A
// user who piped a volume in typed "-" or nothing at all, and "/dev/stdin: ended at byte 960"
// names a file they never gave.
#include <string>

namespace mvox {

std::string input_name(const std::string& path);

}  // namespace mvox
