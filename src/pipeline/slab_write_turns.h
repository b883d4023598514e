#pragma once
// Whose turn it is to write, in the slab-parallel pipeline (slab_extraction.h). The mesh is
// written slab by slab, in order, and each worker writes its own slabs. The worker of the
// lowest slab not yet written writes its engine's output straight into the mesh writer as it
// comes (SlabRecorder::Handover::writer); the workers ahead record theirs in chunks. When a
// slab is written, its writer hands the turn on to the next slab; that slab's worker, at its
// next call or between two slices (poll), writes what it recorded and, if the slab is still
// being extracted, goes on writing straight.
//
// So no thread does nothing but write, the output of the slab being written crosses no
// thread, and recorded output is written by the core that recorded it, while its chunks are
// still in that core's cache. Before, one more thread took every slab's chunks and wrote them,
// and on two cores it took a third of a core from the engines. (A first version of the turns
// had the worker handing the turn on write the next slab itself when it was already extracted;
// that put the writing unevenly on the workers, and a slab's chunks were read on the other core.)
//
// Each worker starts with kChunksPerWorker chunks. A worker ahead of the writer whose chunks
// are all full takes one more, up to `most_chunks` (most_chunks_per_worker); past that, or when
// memory for one more cannot be had, it waits until its turn comes, then writes them itself.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "mvox/engine.h"
#include "pipeline/blocking_queue.h"
#include "pipeline/slab_recorder.h"

namespace mvox {

class MeshWriter;

class SlabWriteTurns {
 public:
  // `slabs` slabs, slab k extracted by worker k mod `workers`, written into `mesh` (may be null:
  // the slabs record nothing, and only their counters are summed). `cancel` stops the run when
  // the writer refuses; waits end when `cancellation` is set and wake() called.
  // Each worker holds at most `most_chunks` chunks (at least kChunksPerWorker).
  // `formatted_bytes_per_polygon` and `formatted_bytes_per_vertex`: for SlabChunk::reserve, when
  // workers format their faces or their vertex lines.
  SlabWriteTurns(MeshWriter* mesh, std::uint32_t slabs, unsigned workers,
                 const EngineOptions& engine, const Cancellation& cancellation,
                 std::function<void()> cancel, unsigned most_chunks,
                 std::size_t formatted_bytes_per_polygon = 0,
                 std::size_t formatted_bytes_per_vertex = 0);
  ~SlabWriteTurns();

  // Worker w's handover for its recorder. Call start_slab() before each slab it extracts, and
  // finish_worker() after its last: it waits for the turns of the slabs it left recorded and
  // writes them.
  SlabRecorder::Handover& handover(unsigned w);
  void start_slab(unsigned w, std::uint32_t slab);
  void finish_worker(unsigned w);

  // Waits until every slab is written or the run is cancelled, calling `written(k)` on this
  // thread, in order, for k = 1..slabs, once slabs 0..k-1 are written (it looks every 50 ms
  // and at the end). False when cancelled.
  bool wait_written(const std::function<void(std::uint32_t)>& written);
  // Wakes every wait, to see the cancellation.
  void wake();

  // Once every worker has stopped: the writer's status (sink_refused: the writer holds the
  // error), the counters of the slabs written, and the seconds spent writing recorded chunks
  // (the recorders count what they wrote straight).
  Status status() const { return status_; }
  const EngineCounters& counters() const { return replay_.counters(); }
  double replay_seconds() const { return replay_seconds_; }
  // Once every worker has stopped: the most chunks one of them held (kChunksPerWorker unless a
  // worker ahead took more).
  unsigned most_chunks_taken() const;

 private:
  struct Pool;
  class WorkerHandover;

  SlabChunk* take(unsigned w);
  // A new chunk, reserved (SlabChunk::reserve) and kept in `pool`; throws bad_alloc.
  SlabChunk* add_chunk(Pool& pool);
  // A new chunk for worker w while it holds fewer than its most (Pool::most), or null.
  SlabChunk* grow(unsigned w);
  void full(unsigned w, SlabChunk* chunk);
  SlabReplay* writer(unsigned w, SlabChunk* current);
  void refused(Status status);

  // If the turn is at worker w's oldest slab not yet written: writes it when it is extracted
  // (and hands the turn on, and looks again), or starts writing the slab it extracts, with
  // what it recorded of it so far (the recorder's current chunk waits for writer()).
  void catch_up(unsigned w);
  // Writes worker w's recorded chunks, oldest first: all it holds, or with `one_slab` those up
  // to and including the oldest slab's last chunk. Each goes back to w's free chunks.
  void write_recorded(unsigned w, bool one_slab);
  // Replays one chunk and gives it back to worker `w`.
  void write_chunk(unsigned w, SlabChunk* chunk);
  // Replays `chunk` into the writer (unless it has refused already), timed, and empties it.
  void replay_and_clear(SlabChunk& chunk);
  // Slab `slab` - 1 is written: the turn goes to `slab`.
  void hand_on(std::uint32_t slab);
  // Waits for a turn to change (or the run to be cancelled).
  void wait_for_turn(std::unique_lock<std::mutex>& lock);

  SlabReplay replay_;
  std::uint32_t slabs_;
  unsigned workers_;
  EngineOptions engine_;  // what a chunk reserves room for (SlabChunk::reserve)
  std::size_t formatted_bytes_per_polygon_;
  std::size_t formatted_bytes_per_vertex_;
  const Cancellation& cancellation_;
  std::function<void()> cancel_;
  std::mutex mutex_;
  std::condition_variable changed_;  // workers waiting for a turn
  // The caller of wait_written(), woken only when all is written or the run is cancelled: on
  // changed_ it was woken with every waiting worker, and took a core from a worker each time.
  std::condition_variable all_written_;
  std::atomic<std::uint32_t> turn_{0};  // the lowest slab not written yet
  std::vector<Pool> pools_;
  std::vector<std::unique_ptr<WorkerHandover>> handovers_;
  unsigned waiting_workers_ = 0;  // in take(), waiting for a chunk or their turn
  Status status_ = Status::ok;
  double replay_seconds_ = 0;  // writing recorded chunks (by whichever thread had the turn)
};

}  // namespace mvox
