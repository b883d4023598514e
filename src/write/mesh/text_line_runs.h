#pragma once
// Text lines made straight into a sink's buffer, a run of lines at a time: the vertex and face
// lines of OBJ and ASCII PLY (obj_writer.cpp, ply_writer.cpp). A write call per line cost more
// than making the line. A Sink has reserve(bytes) and commit(bytes), as binary_records.h says.
#include <algorithm>
#include <cstddef>

#include "write/buffered_writer.h"

namespace mvox {

// The lines of items 0 .. count - 1 into `sink`: put_line(out, i) writes item i's line at `out`,
// at most `most_bytes` (the room reserved for it), and returns the end of what it wrote.
template <class Sink, class PutLine>
void put_line_runs(Sink& sink, std::size_t count, std::size_t most_bytes, PutLine put_line) {
  const std::size_t per_run = BufferedWriter::kBufferBytes / most_bytes;
  for (std::size_t first = 0; first < count; first += per_run) {
    const std::size_t run = std::min(per_run, count - first);
    char* const begin = static_cast<char*>(static_cast<void*>(sink.reserve(run * most_bytes)));
    char* out = begin;
    for (std::size_t i = first; i < first + run; ++i) out = put_line(out, i);
    sink.commit(static_cast<std::size_t>(out - begin));
  }
}

}  // namespace mvox
