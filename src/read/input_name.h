#pragma once
// How messages name an input path: a path that names this process's standard input rather than
// a file (/dev/stdin, /dev/fd/0, /proc/self/fd/0; "-" on the command line becomes /dev/stdin) is
// named "standard input", and any other path as given. A user who piped a volume in typed "-" or
// nothing at all, and "/dev/stdin: ended at byte 960" names a file they never gave. Other
// descriptors keep their path: /dev/fd/63 is what the shell gave for <(zcat scan.raw.gz), and
// what `ps` shows.
#include <string>

namespace mvox {

std::string input_name(const std::string& path);

}  // namespace mvox
