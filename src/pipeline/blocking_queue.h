#pragma once
// A first-in first-out queue between threads, bounded by what its users put in it (they recycle
// a fixed set of items), whose waits end when the run is cancelled: the slab pipeline's threads
// hand slices and recorded output through these, and one failure must stop them all.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

namespace mvox {

// Shared by every queue of one run: set once, and every wait returns.
class Cancellation {
 public:
  bool cancelled() const { return cancelled_.load(std::memory_order_acquire); }
  void cancel() { cancelled_.store(true, std::memory_order_release); }
  // For set_reads_cancelled_by (read_cancellation.h): a reading thread's reads stop with it.
  const std::atomic<bool>* flag() const { return &cancelled_; }

 private:
  std::atomic<bool> cancelled_{false};
};

template <class T>
class BlockingQueue {
 public:
  explicit BlockingQueue(const Cancellation& cancellation) : cancellation_(cancellation) {}

  void push(T item) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      items_.push_back(std::move(item));
    }
    ready_.notify_one();
  }

  // The oldest item; empty only when the run was cancelled (wake() after cancel()).
  std::optional<T> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return !items_.empty() || cancellation_.cancelled(); });
    if (cancellation_.cancelled()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    return item;
  }

  // Wakes every waiter, to see the cancellation.
  void wake() {
    { std::lock_guard<std::mutex> lock(mutex_); }
    ready_.notify_all();
  }

 private:
  const Cancellation& cancellation_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<T> items_;
};

}  // namespace mvox
