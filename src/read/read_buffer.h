#pragma once
// The buffers that file data is read into start on a page boundary. The kernel copies file
// data into a destination that is not 64-byte aligned several times slower: on this project's
// test machine (AMD EPYC), pread of a page-cached file in 1 MiB slices into malloc's buffers,
// which start 16 bytes past a boundary, took 0.55 s per GiB against 0.14 s into aligned ones, and
// that was 40% of a 1024^3 raw-to-PLY run on one thread. A page rather than 64 bytes, so that
// the rule does not depend on which copy routine the kernel picks.
#include <cstddef>
#include <new>
#include <vector>

namespace mvox {

template <class T>
struct PageAlignedAllocator {
  using value_type = T;
  static constexpr std::align_val_t kAlignment{4096};

  PageAlignedAllocator() = default;
  template <class U>
  PageAlignedAllocator(const PageAlignedAllocator<U>&) noexcept {}

  T* allocate(std::size_t count) {
    if (count > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_alloc();
    return static_cast<T*>(::operator new(count * sizeof(T), kAlignment));
  }
  void deallocate(T* pointer, std::size_t) noexcept { ::operator delete(pointer, kAlignment); }

  template <class U>
  bool operator==(const PageAlignedAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const PageAlignedAllocator<U>&) const noexcept { return false; }
};

// Bytes read from a file (a slice, a chunk of slices, a compressed file's input).
using ReadBuffer = std::vector<unsigned char, PageAlignedAllocator<unsigned char>>;

}  // namespace mvox
