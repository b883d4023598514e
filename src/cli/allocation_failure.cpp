// When an allocation fails anywhere in the mvox executable (a library's, a container's), main()
// turns std::bad_alloc into one line naming the input and the size that was asked for
// (failed_allocation.h). The executable replaces the global operator new to learn the size: it
// behaves exactly as the standard one (malloc, the new-handler, std::bad_alloc) and also notes
// the size of a request that fails.
#include <cstdlib>
#include <new>

#include "failed_allocation.h"

// The sanitizers bring operator new and delete of their own, which must stay theirs.
#if defined(__SANITIZE_ADDRESS__)
#define MVOX_OWN_OPERATOR_NEW 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MVOX_OWN_OPERATOR_NEW 0
#endif
#endif
#ifndef MVOX_OWN_OPERATOR_NEW
#define MVOX_OWN_OPERATOR_NEW 1
#endif

namespace {

#if MVOX_OWN_OPERATOR_NEW
// [new.delete.single]: loop on malloc, calling the new-handler, until it succeeds or there is
// no handler; then throw std::bad_alloc. Only the record of the size is added.
void* allocate(std::size_t size) {
  if (size == 0) size = 1;
  for (;;) {
    if (void* memory = std::malloc(size)) return memory;
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) {
      mvox::note_failed_allocation(size);
      throw std::bad_alloc();
    }
    handler();
  }
}
#endif

}  // namespace

#if MVOX_OWN_OPERATOR_NEW
void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete[](void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
void operator delete[](void* memory, std::size_t) noexcept { std::free(memory); }
#endif
