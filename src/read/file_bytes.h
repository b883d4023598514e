#pragma once
// Reading a file's bytes whole (a slice image, a PLY mesh) or its first bytes (a header), the
// one loop every reader of whole files would otherwise write.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "read/read_buffer.h"

namespace mvox {

// Replaces `bytes` with the first min(file size, max_bytes) bytes of `path`, reading to the end
// rather than trusting the size stat reports (pipes and /proc files report 0). `bytes` keeps its
// capacity between calls, so reading one slice after another stops allocating. Throws
// mvox::Error(path, "cannot open file: ...") or (path, "read failed: ...").
void read_file_bytes(const std::string& path, ReadBuffer& bytes,
                     std::uint64_t max_bytes = std::numeric_limits<std::uint64_t>::max());

}  // namespace mvox
