#pragma once
// An array of trivially copyable values whose growth leaves the new values unwritten, for a
// buffer whose every value is written right after it grows: a slab chunk's placed vertices
// (pipeline/slab_recorder.h) and formatted records (formatted_records.h). A std::vector
// value-initialises them first, a pass over everything a slab worker records: without it two
// workers extracted 256x256x1024 in memory in 12.2-12.4 ms instead of 12.7-12.9 ms.
#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>

#include "failed_allocation.h"

namespace mvox {

template <class T>
class UninitializedArray {
  static_assert(std::is_trivially_copyable<T>::value && std::is_trivially_destructible<T>::value,
                "values are moved as bytes and never destroyed");

 public:
  UninitializedArray() = default;
  ~UninitializedArray() { std::free(data_); }
  UninitializedArray(UninitializedArray&& other) noexcept
      : data_(std::exchange(other.data_, nullptr)),
        size_(std::exchange(other.size_, 0)),
        capacity_(std::exchange(other.capacity_, 0)) {}
  UninitializedArray& operator=(UninitializedArray&& other) noexcept {
    std::swap(data_, other.data_);
    std::swap(size_, other.size_);
    std::swap(capacity_, other.capacity_);
    return *this;
  }
  UninitializedArray(const UninitializedArray&) = delete;
  UninitializedArray& operator=(const UninitializedArray&) = delete;

  T* data() { return data_; }
  const T* data() const { return data_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }

  // Room for `count` values, the first size() kept. Throws std::bad_alloc, with the size noted
  // for the message (failed_allocation.h).
  void reserve(std::size_t count) {
    if (count <= capacity_) return;
    if (count > static_cast<std::size_t>(-1) / sizeof(T)) {
      note_failed_allocation(static_cast<std::size_t>(-1));
      throw std::bad_alloc();
    }
    void* const grown = std::realloc(static_cast<void*>(data_), count * sizeof(T));
    if (!grown) {
      note_failed_allocation(count * sizeof(T));
      throw std::bad_alloc();
    }
    data_ = static_cast<T*>(grown);
    capacity_ = count;
  }
  // New values are left unwritten. Grows by half at least, as std::vector.
  void resize(std::size_t count) {
    if (count > capacity_) reserve(std::max(count, capacity_ + capacity_ / 2));
    size_ = count;
  }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace mvox
