#include "pipeline/slab_write_turns.h"

#include <chrono>
#include <utility>

#include "pipeline/slab_extraction.h"
#include "pipeline/stopwatch.h"

namespace mvox {

// One worker's chunks and where its slabs stand. Guarded by SlabWriteTurns::mutex_, except
// `slab` and `writing`, which only the worker's own thread touches.
struct SlabWriteTurns::Pool {
  std::vector<SlabChunk> storage;
  std::vector<SlabChunk*> free;
  std::deque<SlabChunk*> recorded;  // full chunks, oldest first, waiting to be written
  std::uint32_t ended = 0;          // slabs this worker has extracted to the end
  std::uint32_t slab = 0;           // the slab it extracts now
  bool writing = false;             // it has the turn and writes straight
};

class SlabWriteTurns::WorkerHandover final : public SlabRecorder::Handover {
 public:
  WorkerHandover(SlabWriteTurns& turns, unsigned w) : turns_(turns), w_(w) {}
  SlabChunk* take() override { return turns_.take(w_); }
  void full(SlabChunk* chunk) override { turns_.full(w_, chunk); }
  SlabReplay* writer(SlabChunk* current) override { return turns_.writer(w_, current); }
  void refused(Status status) override { turns_.refused(status); }

 private:
  SlabWriteTurns& turns_;
  unsigned w_;
};

SlabWriteTurns::SlabWriteTurns(MeshWriter* mesh, std::uint32_t slabs, unsigned workers,
                               const EngineOptions& engine, const Cancellation& cancellation,
                               std::function<void()> cancel)
    : replay_(mesh),
      slabs_(slabs),
      workers_(workers),
      cancellation_(cancellation),
      cancel_(std::move(cancel)),
      pools_(workers) {
  for (unsigned w = 0; w < workers; ++w) {
    Pool& pool = pools_[w];
    pool.storage.resize(kChunksPerWorker);
    for (SlabChunk& chunk : pool.storage) {
      chunk.reserve(engine);
      pool.free.push_back(&chunk);
    }
    handovers_.push_back(std::make_unique<WorkerHandover>(*this, w));
  }
}

SlabWriteTurns::~SlabWriteTurns() = default;

SlabRecorder::Handover& SlabWriteTurns::handover(unsigned w) { return *handovers_[w]; }

void SlabWriteTurns::start_slab(unsigned w, std::uint32_t slab) {
  pools_[w].slab = slab;
  pools_[w].writing = false;
}

SlabChunk* SlabWriteTurns::take(unsigned w) {
  Pool& pool = pools_[w];
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    if (cancellation_.cancelled()) return nullptr;
    if (!pool.free.empty()) {
      SlabChunk* chunk = pool.free.back();
      pool.free.pop_back();
      return chunk;
    }
    if (!pool.writing && turn_.load(std::memory_order_relaxed) == pool.slab) {
      // Every chunk is recorded output of this slab, whose turn has come: writing it frees them.
      lock.unlock();
      pool.writing = true;
      write_recorded(w, false);
      lock.lock();
      continue;
    }
    ++waiting_workers_;
    changed_.wait(lock);
    --waiting_workers_;
  }
}

SlabReplay* SlabWriteTurns::writer(unsigned w, SlabChunk* current) {
  Pool& pool = pools_[w];
  if (pool.writing) return &replay_;
  if (turn_.load(std::memory_order_acquire) != pool.slab) return nullptr;
  // The turn has come while this worker was recording: what it recorded goes first. Every
  // slab before this one is written, so every chunk it holds is this slab's.
  pool.writing = true;
  write_recorded(w, false);
  const auto start = Clock::now();
  const Status status = replay_.replay(*current);
  replay_seconds_ += seconds_since(start);
  current->clear();
  if (status != Status::ok) refused(status);
  return &replay_;
}

void SlabWriteTurns::full(unsigned w, SlabChunk* chunk) {
  Pool& pool = pools_[w];
  if (!chunk->last) {
    std::lock_guard<std::mutex> lock(mutex_);
    pool.recorded.push_back(chunk);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pool.recorded.push_back(chunk);
    ++pool.ended;
    // Not its turn yet: the slab is left, recorded, to the thread that brings its turn, which
    // decides under this lock too (hand_on).
    if (!pool.writing && turn_.load(std::memory_order_relaxed) != pool.slab) return;
  }
  write_recorded(w, false);
  pool.writing = false;
  hand_on(pool.slab + 1);
}

void SlabWriteTurns::write_recorded(unsigned w, bool one_slab) {
  Pool& pool = pools_[w];
  for (;;) {
    SlabChunk* chunk = nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pool.recorded.empty()) return;
      chunk = pool.recorded.front();
      pool.recorded.pop_front();
    }
    const bool last = chunk->last;
    write_chunk(w, chunk);
    if (one_slab && last) return;
  }
}

void SlabWriteTurns::write_chunk(unsigned w, SlabChunk* chunk) {
  if (status_ == Status::ok) {
    const auto start = Clock::now();
    const Status status = replay_.replay(*chunk);
    replay_seconds_ += seconds_since(start);
    if (status != Status::ok) refused(status);
  }
  chunk->clear();
  bool waiting = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pools_[w].free.push_back(chunk);
    waiting = waiting_workers_ > 0;
  }
  if (waiting) changed_.notify_all();
}

void SlabWriteTurns::hand_on(std::uint32_t slab) {
  for (;; ++slab) {
    bool extracted = false;
    bool wake = false;
    const unsigned owner = slab % workers_;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      turn_.store(slab, std::memory_order_release);
      // Slab `slab` is its owner's (slab / workers_)-th; extracted to the end, it waits recorded.
      extracted = slab < slabs_ && pools_[owner].ended > slab / workers_;
      // Waking a thread costs tens of microseconds here: only a worker waiting for its turn,
      // and the caller of wait_written() once all is written, are woken.
      wake = waiting_workers_ > 0 || slab == slabs_;
    }
    if (wake) changed_.notify_all();
    if (!extracted) return;
    write_recorded(owner, true);
  }
}

void SlabWriteTurns::refused(Status status) {
  // Only the thread with the turn writes, so only it comes here.
  if (status_ == Status::ok) status_ = status;
  cancel_();
}

bool SlabWriteTurns::wait_written(const std::function<void(std::uint32_t)>& written) {
  // Not woken for every slab (hand_on): it looks every kProgressInterval.
  constexpr auto kProgressInterval = std::chrono::milliseconds(50);
  std::uint32_t reported = 0;
  while (reported < slabs_) {
    std::uint32_t turn = 0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait_for(lock, kProgressInterval, [&] {
        return cancellation_.cancelled() || turn_.load(std::memory_order_relaxed) == slabs_;
      });
      if (cancellation_.cancelled()) return false;
      turn = turn_.load(std::memory_order_relaxed);
    }
    while (reported < turn) written(++reported);
  }
  return true;
}

void SlabWriteTurns::wake() {
  { std::lock_guard<std::mutex> lock(mutex_); }
  changed_.notify_all();
}

}  // namespace mvox
