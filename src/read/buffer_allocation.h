#pragma once
// Large buffers sized from a file's header, allocated so that running out of memory is one
// clear line naming the file and the size, never a bare std::bad_alloc.
#include <cstddef>
#include <cstdint>
#include <new>
#include <string>

#include "error.h"
#include "pipeline/memory_plan.h"

namespace mvox {

// Resizes `buffer` (a std::vector of bytes or chars) to `count` elements. Throws
// mvox::Error(subject, "out of memory: cannot allocate 4.0 GiB for WHAT") when the allocation
// fails, or when `count` cannot be addressed at all on this machine.
template <class Buffer>
void resize_buffer(Buffer& buffer, std::uint64_t count, const std::string& subject,
                   const char* what) {
  try {
    if (count > buffer.max_size()) throw std::bad_alloc();
    buffer.resize(static_cast<std::size_t>(count));
  } catch (const std::bad_alloc&) {
    throw Error(subject, "out of memory: cannot allocate " +
                             memory_text(count * sizeof(typename Buffer::value_type)) + " for " +
                             what);
  }
}

}  // namespace mvox
