#include "pipeline/slab_write_turns.h"

#include <algorithm>
#include <chrono>
#include <new>
#include <utility>

#include "pipeline/slab_extraction.h"
#include "pipeline/stopwatch.h"

namespace mvox {

// One worker's chunks and where its slabs stand. Only the worker's own thread touches it: each
// worker writes its own slabs.
struct SlabWriteTurns::Pool {
  std::vector<std::unique_ptr<SlabChunk>> storage;  // kChunksPerWorker, up to `most`
  unsigned most = 0;  // the constructor's most_chunks, or what it had when memory ran out
  std::vector<SlabChunk*> free;
  std::deque<SlabChunk*> recorded;  // full chunks, oldest first, waiting to be written
  std::uint32_t slab = 0;           // the slab it extracts now (or extracted last)
  std::uint32_t ended = 0;          // slabs it has extracted to the end
  std::uint32_t written = 0;        // slabs of its own that are written
  bool writing = false;             // it has the turn for the slab it extracts, and writes straight
};

class SlabWriteTurns::WorkerHandover final : public SlabRecorder::Handover {
 public:
  WorkerHandover(SlabWriteTurns& turns, unsigned w) : turns_(turns), w_(w) {}
  SlabChunk* take() override { return turns_.take(w_); }
  void full(SlabChunk* chunk) override { turns_.full(w_, chunk); }
  SlabReplay* writer(SlabChunk* current) override { return turns_.writer(w_, current); }
  void refused(Status status) override { turns_.refused(status); }
  void poll() override { turns_.catch_up(w_); }

 private:
  SlabWriteTurns& turns_;
  unsigned w_;
};

SlabWriteTurns::SlabWriteTurns(MeshWriter* mesh, std::uint32_t slabs, unsigned workers,
                               const EngineOptions& engine, const Cancellation& cancellation,
                               std::function<void()> cancel, unsigned most_chunks,
                               std::size_t formatted_bytes_per_polygon,
                               std::size_t formatted_bytes_per_vertex)
    : replay_(mesh),
      slabs_(slabs),
      workers_(workers),
      engine_(engine),
      formatted_bytes_per_polygon_(formatted_bytes_per_polygon),
      formatted_bytes_per_vertex_(formatted_bytes_per_vertex),
      cancellation_(cancellation),
      cancel_(std::move(cancel)),
      pools_(workers) {
  for (unsigned w = 0; w < workers; ++w) {
    Pool& pool = pools_[w];
    pool.most = std::max(most_chunks, kChunksPerWorker);
    pool.storage.reserve(pool.most);  // growing then allocates only the chunk
    pool.free.reserve(pool.most);
    for (unsigned c = 0; c < kChunksPerWorker; ++c) pool.free.push_back(add_chunk(pool));
    handovers_.push_back(std::make_unique<WorkerHandover>(*this, w));
  }
}

SlabChunk* SlabWriteTurns::add_chunk(Pool& pool) {
  auto chunk = std::make_unique<SlabChunk>();
  chunk->reserve(engine_, formatted_bytes_per_polygon_, formatted_bytes_per_vertex_);
  pool.storage.push_back(std::move(chunk));
  return pool.storage.back().get();
}

SlabChunk* SlabWriteTurns::grow(unsigned w) {
  Pool& pool = pools_[w];
  if (pool.storage.size() >= pool.most) return nullptr;
  try {
    return add_chunk(pool);
  } catch (const std::bad_alloc&) {
    // It waits for its turn instead, as with all its chunks taken, and tries no more: a later
    // failure would only overwrite the size an out-of-memory message would name.
    pool.most = static_cast<unsigned>(pool.storage.size());
    return nullptr;
  }
}

SlabWriteTurns::~SlabWriteTurns() = default;

unsigned SlabWriteTurns::most_chunks_taken() const {
  std::size_t most = 0;
  for (const Pool& pool : pools_) most = std::max(most, pool.storage.size());
  return static_cast<unsigned>(most);
}

SlabRecorder::Handover& SlabWriteTurns::handover(unsigned w) { return *handovers_[w]; }

void SlabWriteTurns::start_slab(unsigned w, std::uint32_t slab) {
  pools_[w].slab = slab;
  pools_[w].writing = false;
}

void SlabWriteTurns::catch_up(unsigned w) {
  Pool& pool = pools_[w];
  while (!pool.writing && !cancellation_.cancelled()) {
    const std::uint32_t oldest = w + pool.written * workers_;
    if (turn_.load(std::memory_order_acquire) != oldest) return;
    if (pool.written < pool.ended) {
      // An extracted slab, recorded to its last chunk: written, the turn goes on, and it may
      // come back to this worker's next slab.
      write_recorded(w, true);
      ++pool.written;
      hand_on(oldest + 1);
      continue;
    }
    if (oldest != pool.slab) return;  // its next slab has not started: it catches up then
    // The slab it extracts: every chunk it holds is this slab's. From here on it writes straight
    // (the recorder's current chunk goes first, writer()).
    pool.writing = true;
    write_recorded(w, false);
  }
}

SlabChunk* SlabWriteTurns::take(unsigned w) {
  Pool& pool = pools_[w];
  for (;;) {
    if (cancellation_.cancelled()) return nullptr;
    // Its turn may have come: writing what it recorded frees chunks.
    catch_up(w);
    if (!pool.free.empty()) {
      SlabChunk* chunk = pool.free.back();
      pool.free.pop_back();
      return chunk;
    }
    // Every chunk holds output not yet written: one more rather than wait for the turn.
    if (SlabChunk* chunk = grow(w)) return chunk;
    std::unique_lock<std::mutex> lock(mutex_);
    if (turn_.load(std::memory_order_relaxed) != w + pool.written * workers_) wait_for_turn(lock);
  }
}

SlabReplay* SlabWriteTurns::writer(unsigned w, SlabChunk* current) {
  Pool& pool = pools_[w];
  if (!pool.writing) catch_up(w);
  if (!pool.writing) return nullptr;
  // What the recorder's current chunk holds goes before the call: calls recorded before the
  // turn came, or only the slab's start (`first`, taken when the turn had come already).
  if (current->first || !current->calls.empty()) replay_and_clear(*current);
  return &replay_;
}

void SlabWriteTurns::full(unsigned w, SlabChunk* chunk) {
  Pool& pool = pools_[w];
  pool.recorded.push_back(chunk);
  if (!chunk->last) return;
  ++pool.ended;
  if (pool.writing) {
    // Written straight to the end: the last chunk carries only how the slab ended.
    write_recorded(w, true);
    ++pool.written;
    pool.writing = false;
    hand_on(pool.slab + 1);
  }
  catch_up(w);
}

void SlabWriteTurns::finish_worker(unsigned w) {
  Pool& pool = pools_[w];
  for (;;) {
    catch_up(w);
    if (pool.written == pool.ended || cancellation_.cancelled()) return;
    std::unique_lock<std::mutex> lock(mutex_);
    if (turn_.load(std::memory_order_relaxed) != w + pool.written * workers_) wait_for_turn(lock);
  }
}

void SlabWriteTurns::wait_for_turn(std::unique_lock<std::mutex>& lock) {
  const std::uint32_t turn = turn_.load(std::memory_order_relaxed);
  ++waiting_workers_;
  changed_.wait(lock, [&] {
    return cancellation_.cancelled() || turn_.load(std::memory_order_relaxed) != turn;
  });
  --waiting_workers_;
}

void SlabWriteTurns::write_recorded(unsigned w, bool one_slab) {
  Pool& pool = pools_[w];
  while (!pool.recorded.empty()) {
    SlabChunk* chunk = pool.recorded.front();
    pool.recorded.pop_front();
    const bool last = chunk->last;
    write_chunk(w, chunk);
    if (one_slab && last) return;
  }
}

void SlabWriteTurns::write_chunk(unsigned w, SlabChunk* chunk) {
  replay_and_clear(*chunk);
  pools_[w].free.push_back(chunk);
}

void SlabWriteTurns::replay_and_clear(SlabChunk& chunk) {
  // After a refusal nothing more is written: the run is being cancelled.
  if (status_ == Status::ok) {
    const auto start = Clock::now();
    const Status status = replay_.replay(chunk);
    replay_seconds_ += seconds_since(start);
    if (status != Status::ok) refused(status);
  }
  chunk.clear();
}

void SlabWriteTurns::hand_on(std::uint32_t slab) {
  bool wake_workers = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    turn_.store(slab, std::memory_order_release);
    // Waking a thread costs tens of microseconds here: only workers that wait for a turn, and
    // the caller of wait_written() once all is written, are woken. The others see the turn at
    // their next call or between two slices.
    wake_workers = waiting_workers_ > 0;
  }
  if (wake_workers) changed_.notify_all();
  if (slab == slabs_) all_written_.notify_all();
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
      all_written_.wait_for(lock, kProgressInterval, [&] {
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
  all_written_.notify_all();
}

}  // namespace mvox
