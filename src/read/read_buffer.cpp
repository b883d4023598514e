#include "read/read_buffer.h"

#include "failed_allocation.h"

namespace mvox {
namespace {

constexpr std::align_val_t kAlignment{4096};

// The innermost ReadBufferReuse of this thread, or null.
thread_local ReadBufferReuse* t_reuse = nullptr;

}  // namespace

ReadBufferReuse::ReadBufferReuse() : outer_(t_reuse) { t_reuse = this; }

ReadBufferReuse::~ReadBufferReuse() {
  if (kept_) ::operator delete(kept_, kAlignment);
  t_reuse = outer_;
}

namespace detail {

void* allocate_read_buffer(std::size_t bytes) {
  if (ReadBufferReuse* const reuse = t_reuse; reuse && reuse->kept_) {
    void* const kept = reuse->kept_;
    reuse->kept_ = nullptr;
    if (reuse->kept_bytes_ == bytes) return kept;
    // Not this size (an image stack's files differ): returned first, so that the kept block
    // never lies beside a new one and the reader takes no more than its plan says.
    ::operator delete(kept, kAlignment);
  }
  try {
    return ::operator new(bytes, kAlignment);
  } catch (const std::bad_alloc&) {
    note_failed_allocation(bytes);
    throw;
  }
}

void free_read_buffer(void* data, std::size_t bytes) noexcept {
  ReadBufferReuse* const reuse = t_reuse;
  if (!reuse || !data) {
    ::operator delete(data, kAlignment);
    return;
  }
  // The latest block is the likeliest to be asked for again.
  if (reuse->kept_) ::operator delete(reuse->kept_, kAlignment);
  reuse->kept_ = data;
  reuse->kept_bytes_ = bytes;
}

}  // namespace detail
}  // namespace mvox
