#include "cli/allocation_failure.h"

#include <atomic>
#include <cstdlib>
#include <new>

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

std::atomic<std::size_t> g_failed_bytes{0};

#if MVOX_OWN_OPERATOR_NEW
// [new.delete.single]: loop on malloc, calling the new-handler, until it succeeds or there is
// no handler; then throw std::bad_alloc. Only the record of the size is added.
void* allocate(std::size_t size) {
  if (size == 0) size = 1;
  for (;;) {
    if (void* memory = std::malloc(size)) return memory;
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) {
      g_failed_bytes = size;
      throw std::bad_alloc();
    }
    handler();
  }
}
#endif

}  // namespace

namespace mvox {

std::size_t failed_allocation_bytes() { return g_failed_bytes; }

}  // namespace mvox

#if MVOX_OWN_OPERATOR_NEW
void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete[](void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
void operator delete[](void* memory, std::size_t) noexcept { std::free(memory); }
#endif
