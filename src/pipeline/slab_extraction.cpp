#include "pipeline/slab_extraction.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

#include "error.h"
#include "mvox/slice_window.h"
#include "mvox/workspace_buffer.h"
#include "picture/normal_window.h"
#include "picture/picture_layer.h"
#include "picture/surface_picture.h"
#include "pipeline/blocking_queue.h"
#include "pipeline/slab_engine_run.h"
#include "pipeline/slab_picture_follower.h"
#include "pipeline/slab_recorder.h"
#include "pipeline/slab_run_failure.h"
#include "pipeline/slab_write_turns.h"
#include "pipeline/stopwatch.h"
#include "read/range_readable.h"
#include "read/read_buffer.h"
#include "read/read_cancellation.h"
#include "write/mesh/float_texts.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/mesh_writer.h"
#include "write/mesh/vertex_text_formatter.h"

namespace mvox {
namespace {

// The volume cut into slabs of `slab_slices` slices (the last may be thinner).
struct SlabCuts {
  std::uint32_t depth = 0;
  std::uint32_t slab_slices = 1;
  bool normals = false;

  std::uint32_t count() const { return (depth + slab_slices - 1) / slab_slices; }
  std::uint32_t first(std::uint32_t slab) const { return slab * slab_slices; }
  std::uint32_t end(std::uint32_t slab) const { return std::min(depth, first(slab) + slab_slices); }
  SlabSpan span(std::uint32_t slab) const {
    return SlabSpan::of(first(slab), end(slab), depth, normals);
  }
};

struct SliceItem {
  std::uint32_t z = 0;
  ReadBuffer* samples = nullptr;
};

struct Worker {
  Worker(const Cancellation& cancellation, std::size_t slice_bytes, std::uint32_t buffer_slices,
         std::size_t workspace_bytes)
      : slices(cancellation),
        free_slices(cancellation),
        slice_storage(buffer_slices, ReadBuffer(slice_bytes)),
        workspace(workspace_bytes) {
    for (auto& samples : slice_storage) free_slices.push(&samples);
  }

  void wake() {
    slices.wake();
    free_slices.wake();
  }

  BlockingQueue<SliceItem> slices;  // from the reader, in increasing z
  BlockingQueue<ReadBuffer*> free_slices;
  std::vector<ReadBuffer> slice_storage;
  WorkspaceBuffer workspace;
  std::optional<NormalWindow> normals;
  std::unique_ptr<PictureLayer> layer;  // with a picture: this worker's slabs drawn
  // The mesh writer's, when it has one: formats this worker's faces ahead of its turn.
  std::unique_ptr<FaceFormatter> formatter;
  // The writer's vertex lines, for a text format: formatted by the worker for recorded slabs.
  std::unique_ptr<VertexTextFormatter> vertex_text;
  std::thread thread;
  double read_seconds = 0;   // inside its own slab readers
  double write_seconds = 0;  // inside the mesh writer, writing its output straight
};

SliceView packed_view(const VolumeInfo& info, const ReadBuffer& samples) {
  SliceView view;
  view.samples = samples.data();
  view.width = info.width;
  view.height = info.height;
  view.row_stride_bytes = std::size_t{info.width} * sample_bytes(info.type);
  view.type = info.type;
  return view;
}

void copy_slice(const SliceView& from, ReadBuffer& to) {
  const std::size_t row_bytes = std::size_t{from.width} * sample_bytes(from.type);
  const auto* source = static_cast<const unsigned char*>(from.samples);
  if (from.row_stride_bytes == row_bytes) {
    std::memcpy(to.data(), source, row_bytes * from.height);
    return;
  }
  for (std::uint32_t y = 0; y < from.height; ++y)
    std::memcpy(to.data() + y * row_bytes, source + y * from.row_stride_bytes, row_bytes);
}

// Reads every slice once and gives it to each slab that needs it, in slab order.
void read_slices(SliceSource& source, const SlabCuts& cuts,
                 std::vector<std::unique_ptr<Worker>>& workers, const std::string& input_label,
                 double* read_seconds) {
  const auto threads = static_cast<std::uint32_t>(workers.size());
  for (std::uint32_t z = 0; z < cuts.depth; ++z) {
    SliceView view;
    const auto start = Clock::now();
    const bool more = source.next_slice(&view);
    *read_seconds += seconds_since(start);
    if (!more) throw slices_ended_early(input_label, z, cuts.depth);
    const std::uint32_t own = z / cuts.slab_slices;
    for (std::uint32_t slab = own == 0 ? 0 : own - 1; slab <= own + 1 && slab < cuts.count();
         ++slab) {
      const SlabSpan span = cuts.span(slab);
      if (z < span.read_from || z >= span.read_to) continue;
      Worker& worker = *workers[slab % threads];
      const std::optional<ReadBuffer*> samples = worker.free_slices.pop();
      if (!samples) return;  // cancelled
      copy_slice(view, **samples);
      worker.slices.push({z, *samples});
    }
  }
  SliceView extra;
  if (source.next_slice(&extra))
    throw Error(input_label,
                "has more slices than the " + std::to_string(cuts.depth) + " its header gives");
}

// A worker's slab slices as the reading thread hands them out.
class HandedOutSlices final : public SlabSlices {
 public:
  HandedOutSlices(Worker& worker, const VolumeInfo& info, const std::string& input_label)
      : worker_(worker), info_(info), input_label_(input_label) {}

  bool next(std::uint32_t z, SliceView* view) override {
    item_ = worker_.slices.pop();
    if (!item_) return false;
    if (item_->z != z) throw Error(input_label_, "internal error: slices out of order");
    *view = packed_view(info_, *item_->samples);
    return true;
  }
  void release() override {
    if (item_) worker_.free_slices.push(item_->samples);
    item_.reset();
  }

 private:
  Worker& worker_;
  const VolumeInfo& info_;
  const std::string& input_label_;
  std::optional<SliceItem> item_;
};

// Runs the engine over every slab this worker takes: slabs w, w + threads, ...
void extract_slabs(Worker& worker, std::uint32_t index, std::uint32_t threads, const SlabCuts& cuts,
                   const VolumeInfo& info, double threshold, const EngineOptions& options,
                   const VertexPlacement* placement, bool mesh_normals, const RangeReadable* ranges,
                   SlabWriteTurns& turns, SlabPictureFollower* follower, SlabRunFailure& failure,
                   const std::string& input_label) {
  // Each slab's reader gets the buffers of the one before it (read_buffer.h).
  const ReadBufferReuse reuse_read_buffers;
  const Cancellation& cancellation = failure.cancellation();
  const VertexNormals* normals =
      worker.normals && mesh_normals ? &worker.normals->normals() : nullptr;
  SliceWindow* window = worker.normals ? &worker.normals->window() : nullptr;
  SlabRecorder recorder(turns.handover(index), placement, normals,
                        options.polygon_geometry && placement, worker.formatter.get(),
                        worker.vertex_text.get());
  PolygonSink* drawing = worker.layer ? &worker.layer->sink() : nullptr;
  struct CountWrites {
    Worker& worker;
    const SlabRecorder& recorder;
    ~CountWrites() { worker.write_seconds = recorder.write_seconds(); }
  } count_writes{worker, recorder};
  for (std::uint32_t slab = index; slab < cuts.count(); slab += threads) {
    const SlabSpan span = cuts.span(slab);
    turns.start_slab(index, slab);
    if (worker.layer) worker.layer->start_slab(slab);
    std::unique_ptr<SliceSource> reader;  // the slab's own, when the input allows
    std::optional<OwnReaderSlices> own;
    std::optional<HandedOutSlices> handed;
    SlabSlices* slices = nullptr;
    if (ranges) {
      try {
        reader = ranges->open_range(span.read_from, span.read_to);
      } catch (...) {
        failure.fail_reading(span.read_from, std::current_exception());
        return;
      }
      // A reading failure is reported with its slice number, so that the run can report the
      // first bad slice of the volume.
      own.emplace(*reader, input_label, cuts.depth, &cancellation,
                  [&failure](std::uint32_t z, std::exception_ptr error) {
                    failure.fail_reading(z, std::move(error));
                  });
      slices = &*own;
    } else {
      slices = &handed.emplace(worker, info, input_label);
    }
    const bool went_on = extract_slab(span, info, threshold, options, worker.workspace.data(),
                                      worker.workspace.bytes(), recorder, drawing, window, *slices,
                                      cancellation, input_label);
    if (own) worker.read_seconds += own->read_seconds();
    if (!went_on) return;
    if (follower) follower->slab_drawn(index, slab, *worker.layer);
  }
  // Slabs it finished ahead of their turn wait, recorded, for this worker to write them.
  turns.finish_worker(index);
}

}  // namespace

std::uint32_t default_slab_slices(const VolumeInfo& volume) {
  const std::uint64_t slice = std::max<std::uint64_t>(
      1, std::uint64_t{volume.width} * volume.height * sample_bytes(volume.type));
  return static_cast<std::uint32_t>(
      std::clamp<std::uint64_t>((std::uint64_t{1} << 20) / slice, 8, 128));
}

const RangeReadable* own_range_reader(const SliceSource& source) {
  const auto* ranges = dynamic_cast<const RangeReadable*>(&source);
  return ranges && ranges->range_readable() ? ranges : nullptr;
}

unsigned most_chunks_per_worker(const VolumeInfo& volume, std::uint32_t slab_slices) {
  const std::uint64_t voxels = std::uint64_t{volume.width} * volume.height * slab_slices;
  const std::uint64_t chunks = (voxels + SlabRecorder::kChunkBytes - 1) / SlabRecorder::kChunkBytes;
  return static_cast<unsigned>(std::clamp<std::uint64_t>(chunks, kFewestMostChunks, kMostChunks));
}

std::uint32_t slab_buffer_slices(std::uint32_t slab_slices, bool normals) {
  return slab_slices + 1 + (normals ? 2 : 0);
}

std::uint32_t slab_slices_of(const VolumeInfo& volume, std::uint32_t requested) {
  return requested == 0 ? default_slab_slices(volume) : std::max<std::uint32_t>(4, requested);
}

std::uint32_t slab_count(const VolumeInfo& volume, std::uint32_t requested) {
  SlabCuts cuts;
  cuts.depth = volume.depth;
  cuts.slab_slices = slab_slices_of(volume, requested);
  return cuts.count();
}

namespace {

// What one chunk of a worker reserves (SlabChunk::reserved_bytes) for these options.
std::uint64_t chunk_bytes(const EngineOptions& engine, const SlabOptions& options) {
  return SlabChunk::reserved_bytes(engine, options.formatted_bytes_per_polygon,
                                   options.formatted_bytes_per_vertex);
}

unsigned most_chunks(const VolumeInfo& volume, const SlabOptions& options) {
  return options.most_chunks > 0
             ? std::max(options.most_chunks, kChunksPerWorker)
             : most_chunks_per_worker(volume, slab_slices_of(volume, options.slab_slices));
}

}  // namespace

std::uint64_t slab_chunk_bytes(const EngineOptions& engine, const SlabOptions& options) {
  return options.threads * chunk_bytes(engine, options);
}

std::uint64_t slab_pipeline_bytes(const VolumeInfo& volume, const EngineOptions& engine,
                                  const SlabOptions& options) {
  const std::uint64_t slice =
      std::uint64_t{volume.width} * volume.height * sample_bytes(volume.type);
  const std::uint64_t per_worker =
      engine_workspace_bytes(volume.width, volume.height, engine) +
      (options.reader_bytes > 0
           ? options.reader_bytes
           : std::uint64_t{slab_buffer_slices(slab_slices_of(volume, options.slab_slices),
                                              options.needs_window())} *
                 slice) +
      (options.needs_window() ? kSliceWindowDepth * slice : 0) +
      most_chunks(volume, options) * chunk_bytes(engine, options) +
      // A worker's FaceFormatter is a MeshWriter with the batches of one; its
      // VertexTextFormatter has texts of floats of its own.
      (options.formatted_bytes_per_polygon > 0 ? kMeshWriterBatchBytes : 0) +
      (options.formatted_bytes_per_vertex > 0 ? FloatTexts::kBytes : 0) +
      // The recorder's one placed batch (written straight, or made into vertex lines) and its
      // normals.
      std::uint64_t{engine.vertices_per_batch} * sizeof(WorldVertex) +
      (options.normals ? std::uint64_t{engine.vertices_per_batch} * sizeof(glm::vec3) : 0);
  return per_worker * options.threads;
}

PipelineResult run_slab_pipeline(SliceSource& source, double threshold, const EngineOptions& engine,
                                 MeshWriter* mesh, const SlabOptions& options,
                                 const std::string& input_label, const ProgressCallback& progress) {
  const VolumeInfo& info = source.info();
  PipelineResult result;
  result.workspace_bytes = engine_workspace_bytes(info.width, info.height, engine);
  if (result.workspace_bytes == 0)
    throw Error(input_label, "slices of " + std::to_string(info.width) + "x" +
                                 std::to_string(info.height) + " voxels are too large to extract");
  SlabCuts cuts;
  cuts.depth = info.depth;
  cuts.slab_slices = slab_slices_of(info, options.slab_slices);
  const bool window = options.needs_window();
  cuts.normals = window;
  const RangeReadable* ranges = own_range_reader(source);
  // At most one worker per slab. A pipe's slices come in order, once: one worker would get the
  // slices that two slabs with normals share interleaved, so two take turns instead.
  std::uint32_t threads = std::clamp(options.threads, 1u, std::max(1u, cuts.count()));
  if (threads == 1 && window && !ranges && cuts.count() > 1) threads = 2;
  const std::size_t slice_bytes = std::size_t{info.width} * info.height * sample_bytes(info.type);

  std::vector<std::unique_ptr<Worker>> workers;
  std::unique_ptr<SlabWriteTurns> turns;
  SlabRunFailure failure([&workers, &turns] {
    for (auto& worker : workers) worker->wake();
    if (turns) turns->wake();
  });
  // Formatted ahead only with slabs recorded: a polygon batch and its geometry in one chunk.
  std::unique_ptr<FaceFormatter> probe =
      mesh && engine.polygon_geometry ? mesh->face_formatter() : nullptr;
  const std::size_t formatted_bytes = probe ? probe->most_bytes_per_polygon() : 0;
  std::unique_ptr<VertexTextFormatter> vertex_probe =
      mesh ? mesh->vertex_text_formatter() : nullptr;
  const std::size_t vertex_text_bytes = vertex_probe ? vertex_probe->most_bytes_per_vertex() : 0;
  turns = std::make_unique<SlabWriteTurns>(
      mesh, cuts.count(), threads, engine, failure.cancellation(), [&failure] { failure.cancel(); },
      mesh ? most_chunks(info, options) : kChunksPerWorker, formatted_bytes, vertex_text_bytes);
  for (std::uint32_t w = 0; w < threads; ++w) {
    // Workers that read their own slices need no slice buffers from the fan-out.
    const std::uint32_t buffers = ranges ? 0 : slab_buffer_slices(cuts.slab_slices, window);
    workers.push_back(std::make_unique<Worker>(failure.cancellation(), slice_bytes, buffers,
                                               result.workspace_bytes));
    Worker& worker = *workers.back();
    if (probe) worker.formatter = w == 0 ? std::move(probe) : mesh->face_formatter();
    if (vertex_probe)
      worker.vertex_text = w == 0 ? std::move(vertex_probe) : mesh->vertex_text_formatter();
    if (window) worker.normals.emplace(info, options.spacing, input_label);
    if (options.picture)
      worker.layer =
          options.picture->new_layer(worker.normals ? &worker.normals->normals() : nullptr);
  }

  // Frames and the live window follow the layers as they grow.
  std::optional<SlabPictureFollower> follower;
  if (options.picture && options.picture->follows_slices())
    follower.emplace(*options.picture, cuts.count(), cuts.slab_slices, cuts.depth, threads,
                     failure.cancellation());

  const auto start = Clock::now();
  double read_seconds = 0;
  std::thread reader;
  std::atomic<bool> reader_done{false};
  auto join_all = [&] {
    // A cancelled run's reader may be blocked in read() on a silent pipe: wake it until it has
    // stopped (a wake-up can land just before it enters the call, hence the repeats).
    while (reader.joinable() && !reader_done.load()) {
      if (failure.cancellation().cancelled()) wake_blocked_read(reader);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (reader.joinable()) reader.join();
    for (auto& worker : workers)
      if (worker->thread.joinable()) worker->thread.join();
  };
  try {
    for (std::uint32_t w = 0; w < threads; ++w)
      workers[w]->thread = std::thread([&, w] {
        try {
          extract_slabs(*workers[w], w, threads, cuts, info, threshold, engine,
                        mesh ? &mesh->placement() : nullptr, options.normals, ranges, *turns,
                        follower ? &*follower : nullptr, failure, input_label);
        } catch (...) {
          failure.fail(std::current_exception());
        }
      });
    if (!ranges)
      reader = std::thread([&] {
        set_reads_cancelled_by(failure.cancellation().flag());
        try {
          read_slices(source, cuts, workers, input_label, &read_seconds);
        } catch (...) {
          failure.fail(std::current_exception());
        }
        reader_done = true;
      });
  } catch (const std::exception& error) {  // system_error, or bad_alloc for a thread's state
    failure.cancel();
    join_all();
    throw Error(input_label, std::string("cannot start the slab threads: ") + error.what());
  }

  // The workers write, taking turns (slab_write_turns.h); this thread reports progress.
  try {
    turns->wait_written([&](std::uint32_t written) {
      if (follower) follower->show();
      if (progress) progress(cuts.end(written - 1));
    });
  } catch (...) {
    failure.fail(std::current_exception());
  }
  join_all();
  failure.throw_if_failed(ranges);
  result.status = turns->status();
  double write_seconds = turns->replay_seconds();
  for (const auto& worker : workers) {
    read_seconds += worker->read_seconds;
    write_seconds += worker->write_seconds;
  }
  if (options.picture) {
    // Sort-last: the workers' layers into the picture, each pixel to the nearest, ties to the
    // lowest slab, as one engine draws it.
    const auto render_start = Clock::now();
    if (follower) follower->finish();
    for (const auto& worker : workers) options.picture->composite(*worker->layer);
    result.times.render_s = seconds_since(render_start);
  }

  result.counters = turns->counters();
  result.slab_chunks_taken = turns->most_chunks_taken();
  result.times.total_s = seconds_since(start);
  result.times.read_s = read_seconds;
  result.times.write_s = write_seconds;
  // Summed over the workers, the writing can exceed the wall time.
  result.times.extract_s = std::max(0.0, result.times.total_s - write_seconds);
  return result;
}

}  // namespace mvox
