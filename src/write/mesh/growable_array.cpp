#include "write/mesh/growable_array.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>

namespace mvox {
namespace detail {

namespace {

// From this size on an array is a mapping of its own (and can take a kept one). Below it,
// malloc's blocks waste less and cost no system call. Not much higher: malloc hands blocks
// above 128 KiB out as fresh mappings of its own, whose pages fault in one by one.
constexpr std::size_t kMappedBytes = std::size_t{64} << 10;

std::size_t page_bytes() {
  static const std::size_t bytes = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  return bytes;
}

std::size_t whole_pages(std::size_t bytes) {
  const std::size_t page = page_bytes();
  if (bytes > static_cast<std::size_t>(-1) - page) throw std::bad_alloc();
  return (bytes + page - 1) / page * page;
}

// Mappings start on a 2 MiB boundary and span whole 2 MiB, and ask for 2 MiB pages where the
// kernel gives them on request (transparent huge pages in "madvise" mode): the arrays are filled
// once, front to back, and a fault for each 4 KiB page cost more than the filling (a 25 MB mesh
// took 6,100 faults, about a third of mvox.extract's time on this machine).
constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

std::size_t whole_huge_pages(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(-1) - kHugePageBytes) throw std::bad_alloc();
  return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
}

// An inaccessible reservation of `bytes` at a 2 MiB boundary, for a mapping to take its place
// (MAP_FIXED, MREMAP_FIXED): the kernel places neither on such a boundary by itself.
char* aligned_reservation(std::size_t bytes) {
  const std::size_t span = bytes + kHugePageBytes;
  void* area = ::mmap(nullptr, span, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (area == MAP_FAILED) throw std::bad_alloc();
  char* const start = static_cast<char*>(area);
  const std::uintptr_t address = reinterpret_cast<std::uintptr_t>(start);
  char* const aligned = start + (kHugePageBytes - address % kHugePageBytes) % kHugePageBytes;
  if (aligned > start) ::munmap(start, static_cast<std::size_t>(aligned - start));
  char* const end = start + span;
  if (end > aligned + bytes)
    ::munmap(aligned + bytes, static_cast<std::size_t>(end - aligned - bytes));
  return aligned;
}

void huge_pages(void* data, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
  ::madvise(data, bytes, MADV_HUGEPAGE);  // a hint: without it the pages are small, that is all
#endif
}

// Mappings given back lately, for the next arrays to take instead of fresh ones. A fresh mapping
// costs a fault and the kernel's zeroing for every page; a Python caller extracting volume
// after volume would pay that for every mesh (it was a fifth of mvox.extract's time on MRbrain
// with 2 MiB pages). malloc keeps freed blocks for the same reason. At most kPoolBytes are
// kept, and as MADV_FREE: the kernel may take their pages back whenever it needs memory, after
// which reusing them costs what a fresh mapping does.
class MappingPool {
 public:
  static constexpr std::size_t kPoolBytes = std::size_t{64} << 20;
  static constexpr std::size_t kEntries = 6;

  struct Mapping {
    void* data = nullptr;
    std::size_t bytes = 0;
  };

  // The smallest kept mapping of at least `bytes`, or none.
  Mapping take(std::size_t bytes) {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::size_t best = kEntries;
    for (std::size_t i = 0; i < count_; ++i)
      if (kept_[i].bytes >= bytes && (best == kEntries || kept_[i].bytes < kept_[best].bytes))
        best = i;
    if (best == kEntries) return {};
    const Mapping mapping = kept_[best];
    kept_[best] = kept_[--count_];
    kept_bytes_ -= mapping.bytes;
    return mapping;
  }

  // Keeps `mapping`, giving back the oldest kept ones to make room, or unmaps it when it is too
  // large to keep.
  void give(Mapping mapping) {
    if (mapping.bytes > kPoolBytes) {
      ::munmap(mapping.data, mapping.bytes);
      return;
    }
#ifdef MADV_FREE
    ::madvise(mapping.data, mapping.bytes, MADV_FREE);
#endif
    const std::lock_guard<std::mutex> lock(mutex_);
    while (count_ == kEntries || kept_bytes_ + mapping.bytes > kPoolBytes) {
      ::munmap(kept_[0].data, kept_[0].bytes);
      kept_bytes_ -= kept_[0].bytes;
      for (std::size_t i = 1; i < count_; ++i) kept_[i - 1] = kept_[i];
      --count_;
    }
    kept_[count_++] = mapping;
    kept_bytes_ += mapping.bytes;
  }

 private:
  std::mutex mutex_;
  Mapping kept_[kEntries];  // oldest first
  std::size_t count_ = 0;
  std::size_t kept_bytes_ = 0;
};

// Never destroyed: arrays owned by Python objects may be released while the process exits.
MappingPool& mapping_pool() {
  static MappingPool* const pool = new MappingPool;
  return *pool;
}

}  // namespace

void GrowableBytes::reserve(std::size_t wanted, std::size_t used) {
  try {
    grow(wanted, used);
  } catch (const std::bad_alloc&) {
    note_failed_allocation(wanted);
    throw;
  }
}

void GrowableBytes::grow(std::size_t wanted, std::size_t used) {
  if (wanted <= capacity) return;
  if (wanted < kMappedBytes) {
    void* grown = std::realloc(data, wanted);
    if (grown == nullptr) throw std::bad_alloc();
    data = grown;
    capacity = wanted;
    return;
  }
  const std::size_t bytes = whole_huge_pages(wanted);
  if (mapped) {
    // In place when the addresses after it are free, else moved to a fresh reservation: either
    // way the pages it holds are not copied. (Not into a kept mapping: moving its pages over the
    // start of one leaves the two apart in the kernel, and the next mremap of the whole range
    // fails.)
    void* grown = ::mremap(data, capacity, bytes, 0);
    if (grown == MAP_FAILED) {
      char* const destination = aligned_reservation(bytes);
      grown = ::mremap(data, capacity, bytes, MREMAP_MAYMOVE | MREMAP_FIXED, destination);
      if (grown == MAP_FAILED) {
        ::munmap(destination, bytes);
        throw std::bad_alloc();
      }
    }
    data = grown;
    capacity = bytes;
    huge_pages(data, capacity);
    return;
  }
  const MappingPool::Mapping kept = mapping_pool().take(bytes);
  if (kept.data != nullptr) {
    if (used > 0) std::memcpy(kept.data, data, used);
    std::free(data);
    data = kept.data;
    capacity = kept.bytes;
    mapped = true;
    return;
  }
  char* const destination = aligned_reservation(bytes);
  void* mapping = ::mmap(destination, bytes, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0);
  if (mapping == MAP_FAILED) {
    ::munmap(destination, bytes);
    throw std::bad_alloc();
  }
  huge_pages(mapping, bytes);
  if (used > 0) std::memcpy(mapping, data, used);  // from malloc's block, once
  std::free(data);
  data = mapping;
  capacity = bytes;
  mapped = true;
}

void GrowableBytes::shrink(std::size_t used) noexcept {
  if (!mapped) {
    if (used == 0 || used == capacity) return;
    void* shrunk = std::realloc(data, used);
    if (shrunk == nullptr) return;  // keeping the larger block is harmless
    data = shrunk;
    capacity = used;
    return;
  }
  const std::size_t bytes = used == 0 ? page_bytes() : whole_pages(used);
  if (bytes >= capacity) return;
  // The tail's pages are returned; the array stays where it is.
  if (::munmap(static_cast<char*>(data) + bytes, capacity - bytes) == 0) capacity = bytes;
}

void GrowableBytes::release() noexcept {
  if (mapped)
    mapping_pool().give({data, capacity});
  else
    std::free(data);
  data = nullptr;
  capacity = 0;
  mapped = false;
}

}  // namespace detail
}  // namespace mvox
