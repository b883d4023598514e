// The allocator that traps: every way this program could take heap memory halts with a message
// instead. The engine (firmware_like/) promises to allocate nothing, so a run that reaches its
// results has shown it on the board. Also the other ways out that would otherwise end silently
// or differently per platform: abort(), a pure virtual call, a failed MVOX_ASSERT.
//
// Both builds replace every form of operator new and delete (replaceable by the standard). The
// board build also replaces newlib's C allocator (malloc and its reentrant _r forms, which
// newlib's own code calls), abort() and the pure-virtual handler; the host keeps glibc's, which
// its C runtime uses before main.
#include <cstddef>
#include <new>

#include "mvox/assert.h"
#include "platform.h"

namespace mvox::firmware {

void halt_on_assert(const char* expression, const char* file, int line) {
  console_write("assertion failed: ");
  console_write(expression);
  console_write(" at ");
  console_write(file);
  console_write(":");
  console_write_decimal(static_cast<std::uint64_t>(line));
  console_write("\n");
  halt("MVOX_ASSERT");
}

namespace {

[[noreturn]] void allocation(const char* function) {
  console_write("allocation through ");
  console_write(function);
  console_write("\n");
  halt("the program tried to allocate (no heap)");
}

// Deleting a null pointer is allowed and frees nothing; anything else was allocated by someone.
void deallocation(void* pointer, const char* function) {
  if (pointer != nullptr) allocation(function);
}

}  // namespace
}  // namespace mvox::firmware

using mvox::firmware::allocation;
using mvox::firmware::deallocation;

void* operator new(std::size_t) { allocation("operator new"); }
void* operator new[](std::size_t) { allocation("operator new[]"); }
void* operator new(std::size_t, const std::nothrow_t&) noexcept { allocation("operator new"); }
void* operator new[](std::size_t, const std::nothrow_t&) noexcept { allocation("operator new[]"); }
void* operator new(std::size_t, std::align_val_t) { allocation("operator new"); }
void* operator new[](std::size_t, std::align_val_t) { allocation("operator new[]"); }
void* operator new(std::size_t, std::align_val_t, const std::nothrow_t&) noexcept {
  allocation("operator new");
}
void* operator new[](std::size_t, std::align_val_t, const std::nothrow_t&) noexcept {
  allocation("operator new[]");
}
void operator delete(void* p) noexcept { deallocation(p, "operator delete"); }
void operator delete[](void* p) noexcept { deallocation(p, "operator delete[]"); }
void operator delete(void* p, std::size_t) noexcept { deallocation(p, "operator delete"); }
void operator delete[](void* p, std::size_t) noexcept { deallocation(p, "operator delete[]"); }
void operator delete(void* p, const std::nothrow_t&) noexcept {
  deallocation(p, "operator delete");
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  deallocation(p, "operator delete[]");
}
void operator delete(void* p, std::align_val_t) noexcept { deallocation(p, "operator delete"); }
void operator delete[](void* p, std::align_val_t) noexcept { deallocation(p, "operator delete[]"); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  deallocation(p, "operator delete");
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  deallocation(p, "operator delete[]");
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  deallocation(p, "operator delete");
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  deallocation(p, "operator delete[]");
}

#if defined(__arm__)
// newlib's allocator: the public functions and the reentrant forms its stdio, atexit and
// signal code call directly. Defining them all keeps newlib's malloc (nano-mallocr) out of the
// image altogether; scripts/firmware_demo.sh checks that its symbols are absent.
struct _reent;
extern "C" {
void* malloc(std::size_t) { allocation("malloc"); }
void* calloc(std::size_t, std::size_t) { allocation("calloc"); }
void* realloc(void*, std::size_t) { allocation("realloc"); }
void* memalign(std::size_t, std::size_t) { allocation("memalign"); }
void* aligned_alloc(std::size_t, std::size_t) { allocation("aligned_alloc"); }
void free(void* p) { deallocation(p, "free"); }
void* _malloc_r(_reent*, std::size_t) { allocation("malloc"); }
void* _calloc_r(_reent*, std::size_t, std::size_t) { allocation("calloc"); }
void* _realloc_r(_reent*, void*, std::size_t) { allocation("realloc"); }
void* _memalign_r(_reent*, std::size_t, std::size_t) { allocation("memalign"); }
void _free_r(_reent*, void* p) { deallocation(p, "free"); }

// newlib's abort() raises SIGABRT, and its signal table is allocated on first use.
void abort() { mvox::firmware::halt("abort()"); }
void __cxa_pure_virtual() { mvox::firmware::halt("pure virtual function called"); }
}
#endif
