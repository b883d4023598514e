#pragma once
// The buffers that file data is read into start on a page boundary. The kernel copies file
// data into a destination that is not 64-byte aligned several times slower: on this project's
// test machine (AMD EPYC), pread of a page-cached file in 1 MiB slices into malloc's buffers,
// which start 16 bytes past a boundary, took 0.55 s per GiB against 0.14 s into aligned ones, and
// that was 40% of a 1024^3 raw-to-PLY run on one thread. A page rather than 64 bytes, so that
// the rule does not depend on which copy routine the kernel picks.
//
// A slab worker opens a reader for every slab it takes (pipeline/slab_extraction.h), and each
// reader allocates its buffer again. From 128 KiB (a 256x256 16-bit slice) malloc maps such a
// block afresh: the worker then faulted in its pages and, on freeing it, unmapped it, which in a
// process with threads on every core interrupts each of them to flush its TLB. Two workers on
// 16-bit samples ran no faster than one. So a thread inside a ReadBufferReuse scope keeps the
// last block it frees and gives it to its next buffer of the same size.
#include <cstddef>
#include <new>
#include <vector>

#include "failed_allocation.h"

namespace mvox {

namespace detail {
void* allocate_read_buffer(std::size_t bytes);
void free_read_buffer(void* data, std::size_t bytes) noexcept;
}  // namespace detail

template <class T>
struct PageAlignedAllocator {
  using value_type = T;

  PageAlignedAllocator() = default;
  template <class U>
  PageAlignedAllocator(const PageAlignedAllocator<U>&) noexcept {}

  // Throws std::bad_alloc with the size noted (failed_allocation.h).
  T* allocate(std::size_t count) {
    if (count > static_cast<std::size_t>(-1) / sizeof(T)) {
      note_failed_allocation(static_cast<std::size_t>(-1));
      throw std::bad_alloc();
    }
    return static_cast<T*>(detail::allocate_read_buffer(count * sizeof(T)));
  }
  void deallocate(T* pointer, std::size_t count) noexcept {
    detail::free_read_buffer(pointer, count * sizeof(T));
  }

  template <class U>
  bool operator==(const PageAlignedAllocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const PageAlignedAllocator<U>&) const noexcept {
    return false;
  }
};

// Bytes read from a file (a slice, a chunk of slices, a compressed file's input).
using ReadBuffer = std::vector<unsigned char, PageAlignedAllocator<unsigned char>>;

// While one lives, its thread keeps the last ReadBuffer block it frees (one block at most, of
// any size) for its next ReadBuffer of exactly that size, instead of returning it; a request of
// another size returns it first, and the block goes when the scope ends. Scopes on one thread
// nest; the innermost keeps.
class ReadBufferReuse {
 public:
  ReadBufferReuse();
  ~ReadBufferReuse();
  ReadBufferReuse(const ReadBufferReuse&) = delete;
  ReadBufferReuse& operator=(const ReadBufferReuse&) = delete;

  // Bytes of the block it keeps now, 0 for none.
  std::size_t kept_bytes() const { return kept_ ? kept_bytes_ : 0; }

 private:
  friend void* detail::allocate_read_buffer(std::size_t bytes);
  friend void detail::free_read_buffer(void* data, std::size_t bytes) noexcept;

  void* kept_ = nullptr;
  std::size_t kept_bytes_ = 0;
  ReadBufferReuse* outer_;
};

}  // namespace mvox
