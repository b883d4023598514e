#include "pipeline/prefetching_source.h"

#include <chrono>
#include <cstring>
#include <new>
#include <system_error>
#include <utility>

#include "read/read_cancellation.h"

namespace mvox {
namespace {

// How long a caller that found no slice ready waits before it looks again, unless woken.
constexpr std::chrono::milliseconds kLookAgain(1);

// A thread's stack is memory too: when the system cannot give one (EAGAIN, say under ulimit -v)
// the run has run out of memory, and is reported as such, naming the input (cli/main.cpp),
// rather than as "Resource temporarily unavailable".
template <class Function>
std::thread start_thread(Function&& function) {
  try {
    return std::thread(std::forward<Function>(function));
  } catch (const std::system_error&) {
    throw std::bad_alloc();
  }
}

}  // namespace

PrefetchingSource::PrefetchingSource(SliceSource& inner, std::size_t batch_bytes)
    : inner_(inner), info_(inner.info()), batch_bytes_(batch_bytes), reader_(start_thread([this] {
        set_reads_cancelled_by(&cancel_reads_);
        read_ahead();
        std::lock_guard<std::mutex> lock(mutex_);
        reader_done_ = true;
        changed_.notify_all();
      })) {}

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

std::uint64_t PrefetchingSource::working_bytes() const {
  const std::uint64_t inner = inner_.working_bytes();
  if (inner == 0) return 0;
  return inner + buffer_bytes(info_, batch_bytes_);
}

void PrefetchingSource::Batch::put(std::size_t index, const SliceView& slice,
                                   std::size_t batch_bytes) {
  if (index == 0) {
    // The first slice sets the batch's shape, and so how many slices it may hold.
    width = slice.width;
    height = slice.height;
    type = slice.type;
    row_bytes = std::size_t{slice.width} * sample_bytes(slice.type);
    slice_bytes = row_bytes * slice.height;
    capacity = slices_per_batch(batch_bytes, slice_bytes);
    if (bytes.size() < capacity * slice_bytes) bytes.resize(capacity * slice_bytes);
  }
  unsigned char* target = bytes.data() + index * slice_bytes;
  const auto* source = static_cast<const unsigned char*>(slice.samples);
  if (slice.row_stride_bytes == row_bytes) {
    std::memcpy(target, source, slice_bytes);
  } else {
    for (std::uint32_t y = 0; y < height; ++y)
      std::memcpy(target + y * row_bytes, source + y * slice.row_stride_bytes, row_bytes);
  }
}

void PrefetchingSource::read_ahead() {
  // A slice read that did not fit the batch being filled (another shape): it starts the next
  // one. Its view stays valid because the inner source is not called again before it is copied.
  SliceView pending;
  bool have_pending = false;
  for (int filling = 0;; filling ^= 1) {
    Batch& batch = batches_[filling];
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return stopping_ || batch.free; });
      if (stopping_) return;
      batch.free = false;
    }
    // The caller reset the batch when it freed it: count 0, not closed.
    std::size_t count = 0;
    bool more = true;
    std::exception_ptr error;
    try {
      for (;;) {
        SliceView slice;
        if (have_pending) {
          slice = pending;
          have_pending = false;
        } else if (!inner_.next_slice(&slice)) {
          more = false;
          break;
        }
        if (count > 0 && !batch.same_shape(slice)) {
          pending = slice;
          have_pending = true;
          break;
        }
        batch.put(count, slice, batch_bytes_);
        // Published without waking the caller: it looks every millisecond (see the header).
        batch.count.store(++count, std::memory_order_release);
        if (cancel_reads_.load(std::memory_order_relaxed)) return;  // the destructor waits
        if (count == batch.capacity) break;
      }
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      batch.closed = true;
      if (!more || error) {
        finished_ = true;
        error_ = error;
      }
    }
    changed_.notify_all();
    if (!more || error) return;
  }
}

std::uint64_t PrefetchingSource::buffer_bytes(const VolumeInfo& info, std::size_t batch_bytes) {
  const std::uint64_t slice_bytes =
      std::uint64_t{info.width} * info.height * sample_bytes(info.type);
  return 2 * slices_per_batch(batch_bytes, static_cast<std::size_t>(slice_bytes)) * slice_bytes;
}

bool PrefetchingSource::wait_for_slice(SliceView* slice) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  struct AddTime {  // on every way out, the rethrow included
    Clock::time_point start;
    double& seconds;
    ~AddTime() { seconds += std::chrono::duration<double>(Clock::now() - start).count(); }
  } add_time{start, seconds_waiting_};
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    Batch& batch = batches_[taking_];
    if (taken_ < batch.count.load(std::memory_order_acquire)) {
      *slice = batch.view(taken_++);
      return true;
    }
    if (batch.closed) {
      // Every slice of the batch has been handed out, and the caller is done with the last
      // one's view (this is the call after): the reader may refill it. On to the other batch.
      batch.count.store(0, std::memory_order_relaxed);
      batch.closed = false;
      batch.free = true;
      changed_.notify_all();
      taking_ ^= 1;
      taken_ = 0;
      continue;
    }
    if (finished_) {
      // Every slice read has been handed out; the inner source ended or failed after them.
      if (error_) std::rethrow_exception(error_);
      return false;
    }
    // Woken when the batch is closed or the input ends; slices published meanwhile are seen
    // at the next look.
    changed_.wait_for(lock, kLookAgain);
  }
}

}  // namespace mvox
