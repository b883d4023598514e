#include "prefetching_source.h"

#include <chrono>
#include <cstring>

#include "read_cancellation.h"

namespace mvox {

PrefetchingSource::PrefetchingSource(SliceSource& inner)
    : inner_(inner), info_(inner.info()), reader_([this] {
        set_reads_cancelled_by(&cancel_reads_);
        read_ahead();
        std::lock_guard<std::mutex> lock(mutex_);
        reader_done_ = true;
        changed_.notify_all();
      }) {}

PrefetchingSource::~PrefetchingSource() {
  std::unique_lock<std::mutex> lock(mutex_);
  stopping_ = true;
  cancel_reads_ = true;
  changed_.notify_all();
  // The reader may be blocked in read() on a pipe whose writer stays silent: wake it until it
  // has stopped (a wake-up can land just before it enters the call, hence the repeats).
  while (!changed_.wait_for(lock, std::chrono::milliseconds(20), [&] { return reader_done_; }))
    wake_blocked_read(reader_);
  lock.unlock();
  reader_.join();
}

void PrefetchingSource::read_ahead() {
  for (;;) {
    Buffer* buffer = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return stopping_ || !buffers_[next_to_read_].filled; });
      if (stopping_) return;
      buffer = &buffers_[next_to_read_];
    }
    // The buffer is the reader's alone until it is marked filled.
    bool more = false;
    std::exception_ptr error;
    try {
      SliceView slice;
      more = inner_.next_slice(&slice);
      if (more) {
        const std::size_t row_bytes = std::size_t{slice.width} * sample_bytes(slice.type);
        buffer->bytes.resize(row_bytes * slice.height);
        for (std::uint32_t y = 0; y < slice.height; ++y)
          std::memcpy(buffer->bytes.data() + y * row_bytes,
                      static_cast<const unsigned char*>(slice.samples) + y * slice.row_stride_bytes,
                      row_bytes);
        buffer->view = slice;
        buffer->view.samples = buffer->bytes.data();
        buffer->view.row_stride_bytes = row_bytes;
      }
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (more && !error) {
        buffer->filled = true;
        next_to_read_ ^= 1;
      } else {
        finished_ = true;
        error_ = error;
      }
    }
    changed_.notify_all();
    if (!more || error) return;
  }
}

std::uint64_t PrefetchingSource::buffer_bytes(const VolumeInfo& info) {
  return 2 * std::uint64_t{info.width} * info.height * sample_bytes(info.type);
}

bool PrefetchingSource::next_slice(SliceView* slice) {
  std::unique_lock<std::mutex> lock(mutex_);
  // The caller is done with the view it got last time: its buffer may be read into again.
  if (held_ >= 0) {
    buffers_[held_].filled = false;
    held_ = -1;
    changed_.notify_all();
  }
  Buffer& next = buffers_[next_to_hand_out_];
  changed_.wait(lock, [&] { return next.filled || finished_; });
  if (!next.filled) {
    // Every slice read has been handed out; the inner source ended or failed after them.
    if (error_) std::rethrow_exception(error_);
    return false;
  }
  *slice = next.view;
  held_ = next_to_hand_out_;
  next_to_hand_out_ ^= 1;
  return true;
}

}  // namespace mvox
