#include "write/deferred_close.h"

#include <unistd.h>

#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace mvox {
namespace {

// The allowing scopes open now and the closing threads they have not joined yet. A
// function-local static; its destructor joins what a scope could not (none, unless a scope
// outlives main).
struct Closing {
  std::mutex mutex;
  int scopes = 0;
  std::vector<std::thread> threads;

  std::vector<std::thread> take_threads() {
    const std::lock_guard<std::mutex> lock(mutex);
    return std::exchange(threads, {});
  }
  ~Closing() {
    for (std::thread& thread : take_threads()) thread.join();
  }
};

Closing& closing() {
  static Closing state;
  return state;
}

}  // namespace

DeferredCloses::DeferredCloses(bool allowed) : active_(allowed) {
  if (!active_) return;
  Closing& state = closing();
  const std::lock_guard<std::mutex> lock(state.mutex);
  ++state.scopes;
}

DeferredCloses::~DeferredCloses() {
  if (!active_) return;
  Closing& state = closing();
  {
    const std::lock_guard<std::mutex> lock(state.mutex);
    --state.scopes;
  }
  // Joins the threads of a scope open on another thread too, if any: they only close a file.
  for (std::thread& thread : state.take_threads()) thread.join();
}

void close_when_unneeded(int fd, unsigned long long bytes) {
  if (fd < 0) return;
  if (bytes >= kDeferredCloseBytes) {
    Closing& state = closing();
    try {
      const std::lock_guard<std::mutex> lock(state.mutex);
      if (state.scopes > 0) {
        // Room first, so that once the thread runs nothing can throw and leave it unjoined.
        state.threads.reserve(state.threads.size() + 1);
        state.threads.emplace_back([fd] { ::close(fd); });
        return;
      }
    } catch (...) {
      // No memory or no thread to be had: closed here, as with one thread.
    }
  }
  ::close(fd);
}

}  // namespace mvox
