#pragma once
// One slab's engine run, from its slices to its recorded output: what every worker of the
// slab-parallel pipeline (slab_extraction.h) does for each slab it takes, and what each process
// of a distributed run (mvox-mpi) does for its one slab.
#include <cstdint>
#include <exception>
#include <functional>
#include <string>

#include "error.h"
#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "mvox/slice_window.h"
#include "pipeline/blocking_queue.h"
#include "pipeline/slab_recorder.h"

namespace mvox {

// The slices one slab takes: its own [first, end) and the ones it reads, [read_from, read_to):
// the slice before `first` too (Engine::begin_slab), and with normals one more on each side,
// for its slice window.
struct SlabSpan {
  std::uint32_t first = 0;
  std::uint32_t end = 0;
  std::uint32_t read_from = 0;
  std::uint32_t read_to = 0;

  // The span of slices [first, end) of a volume `depth` slices deep (first < end <= depth).
  static SlabSpan of(std::uint32_t first, std::uint32_t end, std::uint32_t depth, bool normals);
};

// What one thread reading the volume in order says when it runs out of slices at slice z.
Error slices_ended_early(const std::string& input_label, std::uint32_t z, std::uint32_t depth);

// Where a slab's engine gets its slices from: a reader of its own, or a thread that reads for
// every slab.
class SlabSlices {
 public:
  // Slice z, z going up from the span's read_from one by one. The view stays valid until
  // release(). False: stop, the run is over (cancelled, or the reading failed and the failure
  // has been reported).
  virtual bool next(std::uint32_t z, SliceView* view) = 0;
  // The engine and the window are done with the slice next() gave last.
  virtual void release() {}

 protected:
  ~SlabSlices() = default;
};

// A slab's slices from a reader of its own (RangeReadable::open_range), timed. A reading
// failure, the reader's exception or its running out (the file changed since it was opened),
// goes to `failed` with its slice number and stops the run; with `failed` empty it is thrown.
// A set `cancellation` (may be null) stops the run before the next read.
class OwnReaderSlices final : public SlabSlices {
 public:
  using Failed = std::function<void(std::uint32_t z, std::exception_ptr failure)>;
  OwnReaderSlices(SliceSource& reader, const std::string& input_label, std::uint32_t depth,
                  const Cancellation* cancellation = nullptr, Failed failed = {});

  bool next(std::uint32_t z, SliceView* view) override;
  // Seconds spent inside the reader.
  double read_seconds() const { return read_seconds_; }

 private:
  SliceSource& reader_;
  const std::string& input_label_;
  std::uint32_t depth_;
  const Cancellation* cancellation_;
  Failed failed_;
  double read_seconds_ = 0;
};

// Runs an engine over `span` into `recorder`: begin_slab() on the slice before it (unless it is
// the volume's first slab), push_slice() on its own slices, and finish() for the volume's last
// slab or finish_slab() for any other. With `window` (restarted here), the engine runs one slice
// behind it, so that normals can be computed from the slices around each vertex batch. The
// recorder gets start(), own_vertices_only() and end() at their places; `drawing` (may be null),
// a picture layer's sink, gets the engine's output too. Returns false when the run stopped:
// `slices` said so, or the recorder found `cancellation` set. Throws mvox::Error naming
// `input_label` for an engine failure.
bool extract_slab(const SlabSpan& span, const VolumeInfo& info, double threshold,
                  const EngineOptions& options, void* workspace, std::size_t workspace_bytes,
                  SlabRecorder& recorder, PolygonSink* drawing, SliceWindow* window,
                  SlabSlices& slices, const Cancellation& cancellation,
                  const std::string& input_label);

}  // namespace mvox
