#include "write/deferred_close.h"

#include <unistd.h>

#include <atomic>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace mvox {
namespace {

// The closing threads not yet joined. A function-local static, so that it is destroyed (and its
// threads joined) at exit after any run that used it.
struct ClosingThreads {
  std::mutex mutex;
  std::vector<std::thread> threads;

  void join_all() {
    std::vector<std::thread> joining;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      joining.swap(threads);
    }
    for (std::thread& thread : joining) thread.join();
  }
  ~ClosingThreads() { join_all(); }
};

ClosingThreads& closing_threads() {
  static ClosingThreads threads;
  return threads;
}

std::atomic<bool> deferred_closes_allowed{true};

}  // namespace

void allow_deferred_closes(bool allowed) { deferred_closes_allowed = allowed; }

void close_when_unneeded(int fd, unsigned long long bytes) {
  if (fd < 0) return;
  if (deferred_closes_allowed && bytes >= kDeferredCloseBytes) {
    ClosingThreads& closing = closing_threads();
    try {
      const std::lock_guard<std::mutex> lock(closing.mutex);
      // Room first, so that once the thread runs nothing can throw and leave it unjoined.
      closing.threads.reserve(closing.threads.size() + 1);
      closing.threads.emplace_back([fd] { ::close(fd); });
      return;
    } catch (...) {
      // No memory or no thread to be had: closed here, as with one thread.
    }
  }
  ::close(fd);
}

void finish_deferred_closes() { closing_threads().join_all(); }

}  // namespace mvox
