#pragma once
// The size of the allocation that failed, for main()'s one line on running out of memory ("out
// of memory: an allocation of 1.5 GiB failed") instead of "std::bad_alloc", which names no size.
// Whatever allocates and throws std::bad_alloc notes the size first: the executable's operator
// new (cli/allocation_failure.cpp) and the library's own arrays (uninitialized_array.h,
// growable_array.h), which take memory from malloc or mmap directly.
#include <cstddef>

namespace mvox {

// Records `bytes` as the most recent failed allocation, from any thread.
void note_failed_allocation(std::size_t bytes);

// Bytes of the most recent allocation that failed, in any thread, or 0 when none has.
std::size_t failed_allocation_bytes();

}  // namespace mvox
