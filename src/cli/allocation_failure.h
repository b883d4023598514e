#pragma once
// When an allocation fails anywhere in the mvox executable (a library's, a container's), main()
// turns std::bad_alloc into one line naming the input and the size that was asked for, instead
// of "std::bad_alloc". The executable replaces the global operator new to learn the size:
// it behaves exactly as the standard one (malloc, the new-handler, std::bad_alloc) and also
// records the size of a request that fails.
#include <cstddef>

namespace mvox {

// Bytes of the most recent allocation through operator new that failed, in any thread, or 0
// (also in builds where the sanitizers own operator new).
std::size_t failed_allocation_bytes();

}  // namespace mvox
