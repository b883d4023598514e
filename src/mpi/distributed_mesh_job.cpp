#include "mpi/distributed_mesh_job.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <vector>

#include "error.h"
#include "mvox/workspace_buffer.h"
#include "picture/normal_window.h"
#include "pipeline/peak_memory.h"
#include "pipeline/slab_engine_run.h"
#include "pipeline/slab_extraction.h"
#include "pipeline/slab_recorder.h"
#include "pipeline/stopwatch.h"
#include "read/range_readable.h"
#include "write/mesh/mesh_writer.h"
#include "write/output_file.h"

namespace mvox {
namespace {

// This rank's slab: slices [depth * r / R, depth * (r + 1) / R). Empty when there are more
// ranks than slices.
SlabSpan rank_span(const VolumeInfo& info, const MpiWorld& world, bool normals) {
  const auto at = [&](int rank) {
    return static_cast<std::uint32_t>(std::uint64_t{info.depth} * static_cast<unsigned>(rank) /
                                      static_cast<unsigned>(world.size()));
  };
  return SlabSpan::of(at(world.rank()), at(world.rank() + 1), info.depth, normals);
}

bool has_slices(const SlabSpan& span) { return span.end > span.first; }

// Slices from the rank's own reader; a reading error is thrown, and reported by the step.
class ReaderSlices final : public SlabSlices {
 public:
  ReaderSlices(SliceSource& reader, const std::string& input_label, std::uint32_t depth)
      : reader_(reader), input_label_(input_label), depth_(depth) {}

  bool next(std::uint32_t z, SliceView* view) override {
    const auto start = Clock::now();
    const bool more = reader_.next_slice(view);
    read_seconds += seconds_since(start);
    if (!more)
      throw Error(input_label_, "ended after " + std::to_string(z) + " of its " +
                                    std::to_string(depth_) + " slices");
    return true;
  }

  double read_seconds = 0;

 private:
  SliceSource& reader_;
  const std::string& input_label_;
  std::uint32_t depth_;
};

// One chunk, reused: the recorder hands it on when full, and it is replayed into the part's
// writer at once (or, counting, only its summary is kept).
class OneChunk final : public SlabRecorder::Handover {
 public:
  OneChunk(const EngineOptions& engine, SlabReplay* replay) : replay_(replay) {
    chunk_.reserve(engine);
  }

  SlabChunk* take() override {
    if (cancellation_.cancelled()) return nullptr;
    chunk_.clear();
    return &chunk_;
  }
  void full(SlabChunk* chunk) override {
    if (chunk->last) summary = chunk->summary;
    // The writer keeps its error; the recorder then finds the run cancelled.
    if (replay_ && replay_->replay(*chunk) != Status::ok) cancellation_.cancel();
  }
  const Cancellation& cancellation() const { return cancellation_; }

  SlabSummary summary;

 private:
  SlabChunk chunk_;
  SlabReplay* replay_;
  Cancellation cancellation_;
};

// Runs this rank's slab into `replay` (null: counting only). Returns the slab's summary.
SlabSummary run_rank_slab(const SlabSpan& span, const RangeReadable& ranges,
                          const VolumeInfo& info, const MeshJob& job,
                          const EngineOptions& engine, const VertexPlacement& placement,
                          SlabReplay* replay, bool normals, double* read_seconds) {
  const std::unique_ptr<SliceSource> reader = ranges.open_range(span.read_from, span.read_to);
  ReaderSlices slices(*reader, job.input_label, info.depth);
  WorkspaceBuffer workspace(engine_workspace_bytes(info.width, info.height, engine));
  std::optional<NormalWindow> window;
  if (normals) window.emplace(info, job.mesh.transform.spacing, job.input_label);
  OneChunk chunk(engine, replay);
  SlabRecorder recorder(chunk, &placement, window ? &window->normals() : nullptr,
                        engine.polygon_geometry);
  const bool done = extract_slab(span, info, job.threshold, engine, workspace.data(),
                                 workspace.bytes(), recorder, nullptr, window ? &window->window() : nullptr,
                                 slices, chunk.cancellation(), job.input_label);
  *read_seconds += slices.read_seconds;
  if (!done) throw Error(job.input_label, "internal error: a rank's slab stopped early");
  return chunk.summary;
}

// What each rank tells the others about its part of the file.
struct PartShape {
  std::uint64_t vertex_bytes = 0;  // the part's bytes that go among the vertices (all, for OBJ, STL)
  std::uint64_t face_bytes = 0;    // those that go among the faces (PLY)
  std::uint64_t faces = 0;
};

struct PartOffsets {
  std::uint64_t vertex_at = 0;
  std::uint64_t face_at = 0;
};

// Where this rank's sections go: after the head and the sections of the ranks before it; PLY's
// faces after every rank's vertices.
PartOffsets part_offsets(const std::vector<PartShape>& shapes, int rank, std::uint64_t head) {
  PartOffsets at;
  at.vertex_at = head;
  std::uint64_t all_vertex_bytes = 0, faces_before = 0;
  for (std::size_t r = 0; r < shapes.size(); ++r) {
    if (static_cast<int>(r) < rank) {
      at.vertex_at += shapes[r].vertex_bytes;
      faces_before += shapes[r].face_bytes;
    }
    all_vertex_bytes += shapes[r].vertex_bytes;
  }
  at.face_at = head + all_vertex_bytes + faces_before;
  return at;
}

// Writes `size` bytes of the file `fd` from `from` into `file` at `at`, a MiB at a time.
void copy_into(MPI_File file, int fd, std::uint64_t from, std::uint64_t size, std::uint64_t at,
               const std::string& subject) {
  std::vector<char> buffer(std::size_t{1} << 20);
  while (size > 0) {
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(size, buffer.size()));
    const ssize_t got = ::pread(fd, buffer.data(), want, static_cast<off_t>(from));
    if (got <= 0)
      throw Error(subject, "cannot read back this rank's part: " +
                               (got < 0 ? errno_text(errno) : std::string("file too short")));
    MPI_Status status;
    const int code = MPI_File_write_at(file, static_cast<MPI_Offset>(at), buffer.data(),
                                       static_cast<int>(got), MPI_BYTE, &status);
    if (code != MPI_SUCCESS) throw Error(subject, "write failed: " + mpi_error_text(code));
    from += static_cast<std::uint64_t>(got);
    at += static_cast<std::uint64_t>(got);
    size -= static_cast<std::uint64_t>(got);
  }
}

void check_distributable(const SliceSource& source, const MeshJob& job) {
  if (job.output.empty())
    throw UsageError("mvox-mpi", "give -o mesh.ply|.stl|.obj: the ranks write one mesh file");
  if (job.picture.wanted())
    throw UsageError("--image", "mvox-mpi writes meshes; draw the picture with mvox extract");
  if (job.output == "-")
    throw UsageError("-o", "mvox-mpi writes a file that every rank writes into; standard output "
                           "cannot be");
  if (job.threads > 1)
    throw UsageError("--threads", "mvox-mpi runs one engine per rank: start more ranks instead");
  if (!own_range_reader(source))
    throw UsageError(job.input_label,
                     "mvox-mpi needs an input every rank can read (files, not a pipe)");
}

MemoryPlan plan_rank_memory(const SliceSource& source, const MeshJob& job,
                            const EngineOptions& engine) {
  const VolumeInfo& info = source.info();
  const std::uint64_t slice = std::uint64_t{info.width} * info.height * sample_bytes(info.type);
  MemoryPlan plan;
  plan.process_bytes = current_resident_bytes();
  plan.add("engine workspace (per rank)", engine_workspace_bytes(info.width, info.height, engine));
  plan.add("reader (slice and decoder buffers)", source.working_bytes());
  if (job.normals) plan.add("slice window (4 slices)", 4 * slice);
  plan.add("recorded output (one chunk)", SlabChunk::reserved_bytes(engine));
  plan.add("mesh writer buffers", mesh_writer_working_bytes(job.format));
  plan.add("copying the part into the mesh", std::uint64_t{1} << 20);
  return plan;
}

}  // namespace

void run_distributed_mesh_job(SliceSource& source, const MeshJob& job, MpiWorld& world) {
  world.join();
  const auto start = Clock::now();
  RunReport report = start_run_report(source, job);
  const VolumeInfo& info = report.volume;
  const SlabSpan span = rank_span(info, world, job.normals);
  const RangeReadable* ranges = own_range_reader(source);
  EngineOptions engine = job.engine;
  // The mesh's options: normals computed by each rank in its own window.
  MeshWriterOptions whole_mesh = job.mesh;
  whole_mesh.normals = nullptr;
  whole_mesh.normals_given = job.normals;
  std::optional<OutputFile> mesh_file;   // rank 0: the whole mesh, published at the end
  std::optional<OutputFile> stats_file;  // rank 0
  world.step([&] {
    check_distributable(source, job);
    check_job_outputs(job, info.depth);
    engine.polygon_geometry = mesh_writer_needs_geometry(job.format, job.mesh);
    if (engine_workspace_bytes(info.width, info.height, engine) == 0)
      throw Error(job.input_label, "slices of " + std::to_string(info.width) + "x" +
                                       std::to_string(info.height) +
                                       " voxels are too large to extract");
    report.memory_plan = plan_rank_memory(source, job, engine);
    report.start_memory_bytes = report.memory_plan.process_bytes;
    report.memory_budget = job.budget;
    check_memory_budget(report.memory_plan, job.budget, job.input_label);
    if (job.dry_run) {
      if (world.rank() == 0) print_dry_run(report, job, report.memory_plan);
      return;
    }
    if (world.rank() == 0) {
      mesh_file.emplace(job.output, job.sync);
      if (!mesh_file->can_overwrite())
        throw UsageError("-o", "mvox-mpi writes a file that every rank writes into; " +
                                   mesh_file->subject() + " is not a regular file");
      if (!job.stats_path.empty()) stats_file.emplace(job.stats_path, job.sync);
    }
  });
  if (job.dry_run) return;

  // 1. Count, and learn where this rank's vertex numbers start.
  double read_seconds = 0;
  SlabSummary mine;
  world.step([&] {
    if (!has_slices(span)) return;
    EngineOptions counting = engine;
    counting.polygon_geometry = false;
    const VertexPlacement placement(job.mesh.transform, false);
    mine = run_rank_slab(span, *ranges, info, job, counting, placement, nullptr, false,
                         &read_seconds);
  });
  const std::vector<SlabSummary> summaries = world.all_gather(mine);
  const std::vector<char> busy = world.all_gather<char>(has_slices(span));
  SlabJoin before, whole;
  for (int r = 0; r < world.size(); ++r) {
    if (!busy[r]) continue;
    if (r < world.rank()) before.end(summaries[r]);
    whole.end(summaries[r]);
  }

  // 2. This rank's part, in a temporary file beside the output.
  std::unique_ptr<MeshWriter> part;
  PartShape shape;
  world.step([&] {
    if (!has_slices(span)) return;
    MeshWriterOptions options = whole_mesh;
    options.part = MeshWriterOptions::Part{before.vertices_before()};
    options.sync = false;
    // Never published: the part is read back from its temporary and deleted with the writer.
    part = open_mesh_writer(job.output + ".part" + std::to_string(world.rank()), job.format,
                            options);
    SlabReplay replay(part.get(), before);
    try {
      run_rank_slab(span, *ranges, info, job, engine, part->placement(), &replay, job.normals,
                    &read_seconds);
    } catch (...) {
      if (part->error()) throw *part->error();  // the writer refused: its error, not the stop
      throw;
    }
    part->complete();
    shape.face_bytes = part->part_face_bytes();
    shape.vertex_bytes = part->output_file()->bytes_written() - shape.face_bytes;
    shape.faces = part->faces_written();
  });
  const auto part_end = Clock::now();

  // 3. Every part into the one file, at its offsets.
  const std::vector<PartShape> shapes = world.all_gather(shape);
  std::uint64_t faces = 0;
  for (const PartShape& s : shapes) faces += s.faces;
  std::string head;
  world.step([&] { head = mesh_file_head(job.format, whole_mesh, whole.counters().vertices, faces); });
  const std::string path = world.broadcast(world.rank() == 0 ? mesh_file->temporary_path() : "");
  MPI_File file = MPI_FILE_NULL;
  const int opened = MPI_File_open(world.comm(), path.c_str(), MPI_MODE_WRONLY, MPI_INFO_NULL,
                                   &file);
  world.step([&] {
    if (opened != MPI_SUCCESS)
      throw Error(job.output, "cannot open for the ranks to write: " + mpi_error_text(opened));
    const std::string& subject = job.output;
    if (world.rank() == 0) {
      MPI_Status status;
      const int code = MPI_File_write_at(file, 0, head.data(), static_cast<int>(head.size()),
                                         MPI_BYTE, &status);
      if (code != MPI_SUCCESS) throw Error(subject, "write failed: " + mpi_error_text(code));
    }
    if (!part) return;
    const PartOffsets at = part_offsets(shapes, world.rank(), head.size());
    const std::string& part_path = part->output_file()->temporary_path();
    const int fd = ::open(part_path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(subject, "cannot read back this rank's part: " + errno_text(errno));
    try {
      copy_into(file, fd, 0, shape.vertex_bytes, at.vertex_at, subject);
      copy_into(file, fd, shape.vertex_bytes, shape.face_bytes, at.face_at, subject);
    } catch (...) {
      ::close(fd);
      throw;
    }
    ::close(fd);
  });
  int synced = MPI_SUCCESS;
  if (job.sync && opened == MPI_SUCCESS) synced = MPI_File_sync(file);
  const int closed = opened == MPI_SUCCESS ? MPI_File_close(&file) : MPI_SUCCESS;
  part.reset();  // deletes this rank's temporary part
  world.step([&] {
    if (synced != MPI_SUCCESS) throw Error(job.output, "sync failed: " + mpi_error_text(synced));
    if (closed != MPI_SUCCESS) throw Error(job.output, "close failed: " + mpi_error_text(closed));
  });

  // Rank 0 makes the mesh and the report appear, as one process would.
  report.result.counters = whole.counters();
  report.result.workspace_bytes = engine_workspace_bytes(info.width, info.height, engine);
  report.format = mesh_format_name(job.format);
  report.faces_written = faces;
  report.result.times.read_s = read_seconds + job.source_open_s;
  report.result.times.extract_s = seconds_since(start) - seconds_since(part_end);
  report.result.times.write_s = seconds_since(part_end);
  report.result.times.total_s = seconds_since(start) + job.source_open_s;
  report.peak_memory_bytes = world.max(peak_resident_bytes());
  world.step([&] {
    if (world.rank() != 0) return;
    mesh_file->seal();
    std::vector<OutputFile*> sealed{&*mesh_file};
    if (stats_file) {
      const std::string json = run_report_json(report);
      stats_file->write(json.data(), json.size());
      stats_file->seal();
      sealed.push_back(&*stats_file);
    }
    publish_together(sealed);
    if (!job.quiet) print_run_summary(report);
  });
}

}  // namespace mvox
