#pragma once
// How a slab-parallel run (slab_extraction.h) fails: the failure it reports is the one one
// thread reading the volume in order would report, whichever thread came to a failure first.
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <utility>

#include "mvox/slice_source.h"
#include "pipeline/blocking_queue.h"
#include "read/range_readable.h"

namespace mvox {

// The failure to report, and the cancellation that stops every thread once there is one.
class SlabRunFailure {
 public:
  // `wake_all` wakes every thread that may wait, to see the cancellation.
  explicit SlabRunFailure(std::function<void()> wake_all) : wake_all_(std::move(wake_all)) {}

  const Cancellation& cancellation() const { return cancellation_; }

  // Stops the run. The writer does this when it refuses a batch: it keeps its own error.
  void cancel() {
    cancellation_.cancel();
    wake_all_();
  }

  // Any failure but reading a worker's own slices: the first one is reported, unless a reading
  // failure came before it. Failures after the run was cancelled are its consequences (a
  // reader told to stop, a worker whose chunks were taken back), not news.
  void fail(std::exception_ptr error) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (cancellation_.cancelled()) return;
      if (!first_ && !read_error_) first_ = std::move(error);
    }
    cancel();
  }

  // A worker reading its own slices failed at slice z. Workers read in parallel, so the first
  // failure to arrive need not be the first bad slice of the volume: throw_if_failed() sees to
  // that. Of failures that arrive together, the lowest slice's is kept.
  void fail_reading(std::uint32_t z, std::exception_ptr error) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (cancellation_.cancelled()) return;
      if (!first_ && (!read_error_ || z < read_z_)) {
        read_error_ = std::move(error);
        read_z_ = z;
      }
    }
    cancel();
  }

  // Throws the failure to report, if any; call once every thread has stopped. For a reading
  // failure at slice z, the slices before z are read again first, in order, on this thread (as
  // long as one thread reading the volume takes to come to z): a bad slice among them, which a
  // worker had not come to when the run was cancelled, is the one to report.
  void throw_if_failed(const RangeReadable* ranges) const {
    if (first_) std::rethrow_exception(first_);
    if (!read_error_) return;
    if (read_z_ > 0) {
      const std::unique_ptr<SliceSource> before = ranges->open_range(0, read_z_);
      SliceView view;
      while (before->next_slice(&view)) {
      }
    }
    std::rethrow_exception(read_error_);
  }

 private:
  std::function<void()> wake_all_;
  Cancellation cancellation_;
  std::mutex mutex_;
  std::exception_ptr first_;
  std::exception_ptr read_error_;
  std::uint32_t read_z_ = 0;
};

}  // namespace mvox
