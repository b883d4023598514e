#include "read/read_buffer.h"

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
  ReadBufferReuse* const reuse = t_reuse;
  if (reuse && reuse->kept_ && reuse->kept_bytes_ == bytes) {
    void* const data = reuse->kept_;
    reuse->kept_ = nullptr;
    return data;
  }
  return ::operator new(bytes, kAlignment);
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
