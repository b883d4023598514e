#pragma once
// Reading a file's bytes whole (a slice image, a PLY mesh) or its first bytes (a header), the
// one loop every reader of whole files would otherwise write.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "read/file_kinds.h"
#include "read/read_buffer.h"

namespace mvox {

// Replaces `bytes` with the first min(file size, max_bytes) bytes of `path`, reading to the end
// rather than trusting the size stat reports (pipes and /proc files report 0). `bytes` keeps its
// capacity between calls, so reading one slice after another stops allocating. Throws
// mvox::Error(path, "cannot open file: ...") or (path, "read failed: ...").
//
// `only_regular`: `path` must be a regular file, and is refused with
// mvox::Error(path, "is no longer a regular file") otherwise, without waiting for a FIFO's writer.
// Slices are listed as regular files and read later, each at its turn: one replaced by a FIFO
// meanwhile kept a run waiting in open() for a writer that never came.
//
// `start`, when it has a check: called once with the file's first min(size, start.bytes) bytes,
// before the rest is read, to throw for a file that is not of its format; so that /dev/zero, or
// 100 GiB of something else, is refused from its first bytes instead of being read whole. It
// returns the most bytes the whole file can hold by what its start says (a binary header's
// element counts), or the largest uint64 when that is not known: a file holding more is refused
// with mvox::Error(path, "holds more than its header describes ...") before it is read.
struct StartCheck {
  std::size_t bytes = 0;
  std::function<std::uint64_t(const unsigned char* start, std::size_t size)> check;
};
void read_file_bytes(const std::string& path, ReadBuffer& bytes,
                     std::uint64_t max_bytes = std::numeric_limits<std::uint64_t>::max(),
                     FileKinds kinds = FileKinds::any, const StartCheck& start = {});

}  // namespace mvox
