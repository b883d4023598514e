#pragma once
// Arrays of numbers that a mesh is collected into when it goes back to a caller in memory (the
// Python module's numpy arrays), grown without copying what they hold.
//
// A std::vector grown by reserve() copies its contents into the new block every time, element
// by element with a custom allocator: collecting MRbrain's mesh (25 MB in three arrays) spent a
// third of mvox.extract's time there. Here an array of 64 KiB or more is its own memory mapping,
// and growing it is mremap(), which moves page-table entries and copies nothing. Smaller arrays
// use malloc and realloc. resize() leaves new numbers uninitialised: the writers fill every one
// right after, and zeroing them first cost as much as copying the mesh once more.
#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <new>
#include <type_traits>
#include <utility>

#include "failed_allocation.h"

namespace mvox {

namespace detail {

// The byte-level work of GrowableArray. Every function throws std::bad_alloc when the memory
// is not there, with the size noted for the message (failed_allocation.h); `bytes` is then
// unchanged.
struct GrowableBytes {
  void* data = nullptr;
  std::size_t capacity = 0;  // bytes
  bool mapped = false;       // its own mapping (mremap grows it), else malloc's

  // Room for at least `wanted` bytes, the first `used` of which are kept.
  void reserve(std::size_t wanted, std::size_t used);
  // Down to `used` bytes (at least one page for a mapping); never moves a mapping.
  void shrink(std::size_t used) noexcept;
  void release() noexcept;

 private:
  // reserve() without noting the size of a failure.
  void grow(std::size_t wanted, std::size_t used);
};

}  // namespace detail

template <class T>
class GrowableArray {
  static_assert(std::is_trivially_copyable<T>::value, "the bytes are moved, not the objects");

 public:
  using value_type = T;

  GrowableArray() = default;
  GrowableArray(std::initializer_list<T> values) {
    resize(values.size());
    std::copy(values.begin(), values.end(), data());
  }
  ~GrowableArray() { bytes_.release(); }
  GrowableArray(GrowableArray&& other) noexcept
      : bytes_(std::exchange(other.bytes_, {})), size_(std::exchange(other.size_, 0)) {}
  GrowableArray& operator=(GrowableArray&& other) noexcept {
    if (this != &other) {
      bytes_.release();
      bytes_ = std::exchange(other.bytes_, {});
      size_ = std::exchange(other.size_, 0);
    }
    return *this;
  }
  GrowableArray(const GrowableArray&) = delete;
  GrowableArray& operator=(const GrowableArray&) = delete;

  T* data() { return static_cast<T*>(bytes_.data); }
  const T* data() const { return static_cast<const T*>(bytes_.data); }
  T* begin() { return data(); }
  T* end() { return data() + size_; }
  const T* begin() const { return data(); }
  const T* end() const { return data() + size_; }
  T& operator[](std::size_t i) { return data()[i]; }
  const T& operator[](std::size_t i) const { return data()[i]; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::size_t capacity() const { return bytes_.capacity / sizeof(T); }

  void reserve(std::size_t count) {
    if (count <= capacity()) return;
    if (count > static_cast<std::size_t>(-1) / sizeof(T)) {
      note_failed_allocation(static_cast<std::size_t>(-1));
      throw std::bad_alloc();
    }
    bytes_.reserve(count * sizeof(T), size_ * sizeof(T));
  }
  // New numbers are left uninitialised. Grows at least by half, as std::vector, so that many
  // small resizes cost amortised constant time.
  void resize(std::size_t count) {
    if (count > capacity()) reserve(std::max(count, capacity() + capacity() / 2));
    size_ = count;
  }
  void clear() { size_ = 0; }
  void shrink_to_fit() { bytes_.shrink(size_ * sizeof(T)); }

 private:
  detail::GrowableBytes bytes_;
  std::size_t size_ = 0;  // numbers
};

}  // namespace mvox
