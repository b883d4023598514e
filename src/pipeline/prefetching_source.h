#pragma once
// Reading overlapped with extraction: a SliceSource that reads (decodes) the next slices on a
// thread of its own while the caller works on the current one. Decoding PNG or TIFF slices can
// take as long as extracting and rendering them, so on a machine with a second core the reading
// mostly disappears from the run's time.
//
// Slices cross between the threads through two batches: each holds as many whole slices as fit
// in `batch_bytes` (64 KiB by default), and always at least one. The reader publishes each slice
// in the batch it fills with an atomic count, and the caller takes it from there without a
// lock; the threads meet under the lock only to pass a whole batch back and forth. Handing each
// slice over under a lock with a wake-up cost a system call and two context switches, tens of
// microseconds, more than a small slice takes to read or extract. Nor does the reader wake the
// caller for each slice it publishes: a caller that finds none ready looks again every
// millisecond, and is woken at once when a batch is full or the input ends. So a slice of
// `batch_bytes` or more still reaches the caller as soon as it is read, as before batches, and a
// slow input (a pipe that trickles, a slice that takes long to decode) within a millisecond of
// each slice, never held back for a batch to fill.
// Memory: two batches, each max(batch_bytes, one slice), fixed.
//
// The inner source is only ever called from the reading thread. Whatever it throws is rethrown
// by next_slice() at the slice where it happened, so errors read exactly as without prefetching.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "mvox/slice_source.h"
#include "read/read_buffer.h"

namespace mvox {

class PrefetchingSource final : public SliceSource {
 public:
  static constexpr std::size_t kDefaultBatchBytes = 64 * 1024;

  // `inner` is borrowed and must outlive this object; reading starts at once.
  explicit PrefetchingSource(SliceSource& inner, std::size_t batch_bytes = kDefaultBatchBytes);
  ~PrefetchingSource() override;  // stops the reading thread, even mid-volume
  PrefetchingSource(const PrefetchingSource&) = delete;
  PrefetchingSource& operator=(const PrefetchingSource&) = delete;

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override {
    // Most calls are answered from the batch in hand, without the lock.
    const Batch& batch = batches_[taking_];
    if (taken_ < batch.count.load(std::memory_order_acquire)) {
      *slice = batch.view(taken_++);
      return true;
    }
    return wait_for_slice(slice);
  }
  // The inner source's working memory and the two batches; 0 when the inner source cannot tell.
  std::uint64_t working_bytes() const override;

  // Seconds next_slice() has spent waiting for the reader so far (caller thread only). Only calls
  // that find no slice ready can wait, so only those are timed: timing every call would cost two
  // clock readings per slice, more than a slice of a few voxels takes to extract.
  double seconds_waiting() const { return seconds_waiting_; }

  // Slices of `slice_bytes` in one batch of at most `batch_bytes`: at least one.
  static std::size_t slices_per_batch(std::size_t batch_bytes, std::size_t slice_bytes) {
    const std::size_t fit = slice_bytes == 0 ? batch_bytes : batch_bytes / slice_bytes;
    return fit > 0 ? fit : 1;
  }

  // The memory this adds to its inner source's for a volume of `info`: its two batches.
  static std::uint64_t buffer_bytes(const VolumeInfo& info,
                                    std::size_t batch_bytes = kDefaultBatchBytes);

 private:
  // Consecutive slices of one shape, rows packed, slice i at byte i * slice_bytes. The reader
  // writes slice `count` and then publishes it by raising `count`; the caller reads slices below
  // `count`. The shape is set with the first slice, before it is published.
  struct Batch {
    // Page-aligned, as read buffers are (read/read_buffer.h): copying a slice into a buffer
    // 16 bytes past a cache-line boundary, as malloc gives, took several times as long.
    ReadBuffer bytes;
    std::uint32_t width = 0, height = 0;
    SampleType type = SampleType::u8;
    std::size_t row_bytes = 0, slice_bytes = 0;
    std::size_t capacity = 0;           // slices the batch may hold
    std::atomic<std::size_t> count{0};  // slices published
    bool closed = false;  // (under the lock) the reader adds no more: full, or the shape changed
    bool free = true;     // (under the lock) the caller is done with it: the reader may refill it

    SliceView view(std::size_t i) const {
      return {bytes.data() + i * slice_bytes, width, height, row_bytes, type};
    }
    bool same_shape(const SliceView& slice) const {
      return slice.width == width && slice.height == height && slice.type == type;
    }
    // Copies `slice` in as slice `index` (the first sets the shape); does not publish it.
    void put(std::size_t index, const SliceView& slice, std::size_t batch_bytes);
  };

  bool wait_for_slice(SliceView* slice);  // the caller, when the batch in hand has no slice ready
  void read_ahead();                      // the reading thread

  SliceSource& inner_;
  const VolumeInfo info_;
  const std::size_t batch_bytes_;
  Batch batches_[2];
  std::mutex mutex_;
  std::condition_variable changed_;
  int taking_ = 0;                         // the batch the caller takes slices from (caller only)
  std::size_t taken_ = 0;                  // slices of it handed out (caller only)
  double seconds_waiting_ = 0;             // in wait_for_slice (caller only)
  bool finished_ = false;                  // the inner source has no more slices (or failed)
  bool stopping_ = false;                  // the destructor wants the reader to stop
  bool reader_done_ = false;               // the reading thread has returned
  std::atomic<bool> cancel_reads_{false};  // read_cancellation.h: give up a blocked read; and
                                           // the reader stops between two slices
  std::exception_ptr error_;  // what the inner source threw, for the slice after the last good
  std::thread reader_;
};

}  // namespace mvox
