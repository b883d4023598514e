#include "mpi/distributed_mesh_job.h"

#include <memory>
#include <optional>
#include <vector>

#include "error.h"
#include "mpi/mpi_file_stream.h"
#include "mpi/picture_reduction.h"
#include "mpi/placed_part_writer.h"
#include "mpi/shared_mesh_file.h"
#include "mvox/workspace_buffer.h"
#include "picture/normal_window.h"
#include "picture/picture_layer.h"
#include "picture/surface_picture.h"
#include "pipeline/peak_memory.h"
#include "pipeline/slab_engine_run.h"
#include "pipeline/slab_extraction.h"
#include "pipeline/slab_recorder.h"
#include "pipeline/stopwatch.h"
#include "read/range_readable.h"
#include "write/mesh/binary_records.h"
#include "write/mesh/mesh_writer.h"
#include "write/mesh/ply_writer.h"
#include "write/output_file.h"
#include "write/slice_image_writer.h"

namespace mvox {
namespace {

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

// The triangles the polygons counted in `c` split into: a polygon of n corners, n - 2.
std::uint64_t triangles_of(const EngineCounters& c) {
  std::uint64_t triangles = 0;
  for (int size = 3; size <= kMaxPolygonVertices; ++size)
    triangles += std::uint64_t(size - 2) * c.polygons_by_size[size];
  return triangles;
}

void check_distributable(const SliceSource& source, const MeshJob& job) {
  if (job.output == "-")
    throw UsageError("-o",
                     "mvox-mpi writes a file that every rank writes into; standard output "
                     "cannot be");
  if (!job.picture.frames_dir.empty() || job.picture.show)
    throw UsageError(job.picture.show ? "--show" : "--frames",
                     "frames and the window are one process's: use mvox extract");
  if (job.threads > 1)
    throw UsageError("--threads", "mvox-mpi runs one engine per rank: start more ranks instead");
  if (job.decimation)
    throw UsageError("--decimate",
                     "the simplification needs the layers on both sides of a slab's boundary, "
                     "which another rank holds: use mvox extract");
  if (job.pieces.active())
    throw UsageError(job.pieces.largest ? "--largest" : "--min-faces",
                     "a piece may cross every rank's slab, and is known only once the whole "
                     "surface is: use mvox extract");
  if (job.smooth_iterations > 0)
    throw UsageError("--smooth",
                     "smoothing needs the layers on both sides of a slab's boundary, which "
                     "another rank holds: use mvox extract");
  if (!own_range_reader(source))
    throw UsageError(job.input_label,
                     "mvox-mpi needs slices every rank can read on its own: image stacks, raw "
                     "slices or volumes, NRRD, MetaImage or NIfTI with raw data, TIFF stacks, "
                     "DICOM series; this input is read in order (a pipe, compressed data, or a "
                     "--tissue range)");
}

// One rank's share of the job, step by step (distributed_mesh_job.h).
class RankRun {
 public:
  RankRun(SliceSource& source, const MeshJob& job, MpiWorld& world)
      : source_(source),
        job_(job),
        world_(world),
        report_(start_run_report(source, job)),
        info_(report_.volume),
        ranges_(own_range_reader(source)),
        engine_(job.engine),
        whole_mesh_(job.mesh),
        placed_(want_mesh() && PlacedPartWriter::places(job.format)) {
    // Normals are computed by each rank in its own window.
    whole_mesh_.normals = nullptr;
    whole_mesh_.normals_given = job.normals;
    window_ = job.normals || (job.picture.wanted() && job.picture.smooth);
    const auto at = [&](int rank) {
      return static_cast<std::uint32_t>(std::uint64_t{info_.depth} * static_cast<unsigned>(rank) /
                                        static_cast<unsigned>(world.size()));
    };
    span_ = SlabSpan::of(at(world.rank()), at(world.rank() + 1), info_.depth, window_);
  }

  // Checks, the memory plan, and rank 0's outputs created. False for a dry run.
  bool prepare();
  // Step 1 (with a mesh): counts, and learns where this rank's vertex numbers start; for parts
  // written in place, also where its records go, and opens the file.
  void count();
  // Step 2: this rank's part of the mesh, and its layer of the picture.
  void extract();
  // Step 3: the parts into the one file; the layers into rank 0's picture.
  void write_together();
  // Rank 0 makes the outputs appear.
  void publish();

 private:
  bool has_slices() const { return span_.end > span_.first; }
  bool want_mesh() const { return !job_.output.empty(); }
  MemoryPlan plan_memory() const;
  // Every rank's summary of its slab: where this rank's vertex numbers start, and the counters.
  void join_summaries(const SlabSummary& mine);
  // Refuses, naming the output, a mesh its format cannot hold, known from the counts.
  void check_format_limits() const;
  // Every rank's part shape from the counts, the head, and the shared file opened.
  void place_parts();
  // The part's shape as the counts give it for `summary`'s slab.
  PartShape planned_shape(const SlabSummary& summary) const;
  // A writer of this rank's part: into the shared file in place, or into a part file.
  std::unique_ptr<MeshWriter> open_part_writer(const MeshWriterOptions& options);
  // Throws unless the part written has the shape the counts planned.
  void check_placed_part() const;
  // Runs this rank's slab: into `replay` (null: nothing recorded) and `layer` (may be null).
  SlabSummary run_slab(const EngineOptions& engine, const VertexPlacement* placement,
                       SlabReplay* replay, bool mesh_normals, bool draw);

  SliceSource& source_;
  const MeshJob& job_;
  MpiWorld& world_;
  RunReport report_;
  const VolumeInfo& info_;
  const RangeReadable* ranges_;
  EngineOptions engine_;
  MeshWriterOptions whole_mesh_;
  bool placed_;  // the part written in place (PlacedPartWriter), not into a part file
  bool window_ = false;
  SlabSpan span_;
  Clock::time_point start_ = Clock::now();
  double read_seconds_ = 0;
  double write_seconds_ = 0;
  std::optional<OutputFile> mesh_file_;    // rank 0
  std::optional<OutputFile> stats_file_;   // rank 0
  std::optional<SurfacePicture> picture_;  // every rank: the camera; rank 0's is the image
  std::optional<NormalWindow> normal_window_;
  std::unique_ptr<PictureLayer> layer_;
  SlabSummary counted_;                 // this rank's slab, from the counting pass
  std::vector<SlabSummary> summaries_;  // every rank's, in rank order
  std::vector<char> busy_;              // whether each rank has slices
  SlabJoin before_, whole_;
  PartShape shape_;
  std::vector<PartShape> shapes_;  // every rank's part
  std::uint64_t faces_ = 0;
  std::string head_;
  std::optional<SharedMeshFile> shared_file_;
  std::optional<MpiFileStream> vertex_stream_, face_stream_;  // placed parts
  std::unique_ptr<MeshWriter> part_;                          // after what it writes into
};

MemoryPlan RankRun::plan_memory() const {
  const std::uint64_t slice = std::uint64_t{info_.width} * info_.height * sample_bytes(info_.type);
  MemoryPlan plan;
  plan.process_bytes = current_resident_bytes();
  plan.add("engine workspace (per rank)",
           engine_workspace_bytes(info_.width, info_.height, engine_));
  plan.add("reader (slice and decoder buffers)", source_.working_bytes());
  if (window_) plan.add("slice window (4 slices)", 4 * slice);
  if (want_mesh()) {
    plan.add("recorded output (one chunk)", SlabChunk::reserved_bytes(engine_));
    if (placed_) {
      plan.add("mesh records, written in place", PlacedPartWriter::working_bytes());
    } else {
      plan.add("mesh writer buffers", mesh_writer_working_bytes(job_.format));
      plan.add("copying the part into the mesh", std::uint64_t{1} << 20);
    }
  }
  if (job_.picture.wanted()) {
    // The picture with its slab numbers, the rank's layer, the reduction's buffers, MPI's own
    // buffer for the tree (about one array of fragments), and the encoded image (rank 0).
    const std::uint32_t w = job_.picture.width, h = job_.picture.height;
    const std::uint64_t pixels = std::uint64_t{w} * h;
    plan.add("picture, layer and compositing",
             zbuffer_workspace_bytes(w, h) + 4 * pixels + PictureLayer::bytes(w, h) +
                 PictureReduction::bytes(w, h) + pixels * sizeof(PictureReduction::Fragment) +
                 2 * pixels);
  }
  return plan;
}

bool RankRun::prepare() {
  world_.step([&] {
    check_distributable(source_, job_);
    check_job_outputs(job_, info_.depth);
    engine_.polygon_geometry = job_.picture.wanted() ||
                               (want_mesh() && mesh_writer_needs_geometry(job_.format, job_.mesh));
    if (engine_workspace_bytes(info_.width, info_.height, engine_) == 0)
      throw Error(job_.input_label, "slices of " + std::to_string(info_.width) + "x" +
                                        std::to_string(info_.height) +
                                        " voxels are too large to extract");
    report_.memory_plan = plan_memory();
    report_.start_memory_bytes = report_.memory_plan.process_bytes;
    report_.memory_budget = job_.budget;
    check_memory_budget(report_.memory_plan, job_.budget, job_.input_label);
    if (job_.dry_run) {
      if (world_.rank() == 0) print_dry_run(report_, job_, report_.memory_plan);
      return;
    }
    if (job_.picture.wanted()) {
      if (!job_.picture.image_path.empty()) initialize_image_codecs(job_.picture.image_path);
      PictureOptions options = job_.picture;
      options.sync = options.sync || job_.sync;
      if (world_.rank() != 0) options.image_path.clear();  // only rank 0 writes it
      const WorldTransform& placement = job_.mesh.transform;
      picture_.emplace(info_, placement.spacing, placement.origin, nullptr, options);
    }
    if (world_.rank() == 0 && want_mesh()) {
      mesh_file_.emplace(job_.output, job_.sync);
      if (!mesh_file_->can_overwrite())
        throw UsageError("-o", "mvox-mpi writes a file that every rank writes into; " +
                                   mesh_file_->subject() + " is not a regular file");
    }
    if (world_.rank() == 0 && !job_.stats_path.empty())
      stats_file_.emplace(job_.stats_path, job_.sync);
  });
  return !job_.dry_run;
}

SlabSummary RankRun::run_slab(const EngineOptions& engine, const VertexPlacement* placement,
                              SlabReplay* replay, bool mesh_normals, bool draw) {
  const bool window = window_ && (mesh_normals || draw);
  // Without a window, no slice beyond the slab and the one before it.
  const SlabSpan span = window ? span_ : SlabSpan::of(span_.first, span_.end, info_.depth, false);
  const std::unique_ptr<SliceSource> reader = ranges_->open_range(span.read_from, span.read_to);
  // A reading error is thrown, and reported by the step.
  OwnReaderSlices slices(*reader, job_.input_label, info_.depth);
  WorkspaceBuffer workspace(engine_workspace_bytes(info_.width, info_.height, engine));
  if (window && !normal_window_)
    normal_window_.emplace(info_, job_.mesh.transform.spacing, job_.input_label);
  const VertexNormals* normals = window ? &normal_window_->normals() : nullptr;
  if (draw) {
    layer_ = picture_->new_layer(normals);
    layer_->start_slab(static_cast<std::uint32_t>(world_.rank()));
  }
  OneChunk chunk(engine, replay);
  SlabRecorder recorder(chunk, placement, mesh_normals ? normals : nullptr,
                        engine.polygon_geometry && placement);
  const bool done = extract_slab(span, info_, job_.threshold, engine, workspace.data(),
                                 workspace.bytes(), recorder, draw ? &layer_->sink() : nullptr,
                                 window ? &normal_window_->window() : nullptr, slices,
                                 chunk.cancellation(), job_.input_label);
  read_seconds_ += slices.read_seconds();
  if (!done) throw Error(job_.input_label, "internal error: a rank's slab stopped early");
  return chunk.summary;
}

void RankRun::count() {
  world_.step([&] {
    if (!has_slices()) return;
    EngineOptions counting = engine_;
    counting.polygon_geometry = false;
    counted_ = run_slab(counting, nullptr, nullptr, false, false);  // nothing recorded
  });
  join_summaries(counted_);
  world_.step([&] { check_format_limits(); });
  if (placed_) place_parts();
}

PartShape RankRun::planned_shape(const SlabSummary& summary) const {
  const EngineCounters& c = summary.counters;
  const std::uint64_t triangles = triangles_of(c);
  std::uint64_t polygon_bytes = 0;
  for (int size = 3; size <= kMaxPolygonVertices; ++size)
    polygon_bytes += ply_face_record_bytes(size) * c.polygons_by_size[size];
  PartShape shape;
  if (job_.format == MeshFormat::stl) {
    shape.faces = triangles;
    shape.vertex_bytes = kStlTriangleBytes * triangles;
    return shape;
  }
  const std::uint64_t own_vertices = c.vertices - c.shared_vertices;
  shape.vertex_bytes = ply_vertex_record_bytes(whole_mesh_.writes_normals()) * own_vertices;
  shape.faces = whole_mesh_.triangulate ? triangles : c.polygons;
  shape.face_bytes = whole_mesh_.triangulate ? ply_face_record_bytes(3) * triangles : polygon_bytes;
  return shape;
}

void RankRun::place_parts() {
  shapes_.assign(summaries_.size(), PartShape{});
  for (std::size_t r = 0; r < summaries_.size(); ++r) {
    if (busy_[r]) shapes_[r] = planned_shape(summaries_[r]);
    faces_ += shapes_[r].faces;
  }
  // check_format_limits() found the head writable.
  head_ = mesh_file_head(job_.format, whole_mesh_, whole_.counters().vertices, faces_);
  const std::string path = world_.broadcast(world_.rank() == 0 ? mesh_file_->temporary_path() : "");
  shared_file_.emplace(world_, path, job_.output);
}

std::unique_ptr<MeshWriter> RankRun::open_part_writer(const MeshWriterOptions& options) {
  if (!placed_) {
    // Never published: the part is read back from its temporary and deleted with the writer.
    return open_mesh_writer(job_.output + ".part" + std::to_string(world_.rank()), job_.format,
                            options);
  }
  const PartOffsets at = part_offsets(shapes_, world_.rank(), head_.size());
  vertex_stream_.emplace(shared_file_->file(), at.vertex_at, job_.output);
  face_stream_.emplace(shared_file_->file(), at.face_at, job_.output);
  return std::make_unique<PlacedPartWriter>(job_.format, options, *vertex_stream_, *face_stream_,
                                            job_.output);
}

void RankRun::check_placed_part() const {
  const auto& written = static_cast<const PlacedPartWriter&>(*part_);
  const PartShape& planned = shapes_[static_cast<std::size_t>(world_.rank())];
  if (written.vertex_bytes() == planned.vertex_bytes &&
      written.face_bytes() == planned.face_bytes && written.faces_written() == planned.faces)
    return;
  throw Error(job_.input_label,
              "changed while being read: slices " + std::to_string(span_.first) + " to " +
                  std::to_string(span_.end - 1) + " gave " + std::to_string(planned.faces) +
                  " faces in " + std::to_string(planned.vertex_bytes + planned.face_bytes) +
                  " bytes, then " + std::to_string(written.faces_written()) + " in " +
                  std::to_string(written.vertex_bytes() + written.face_bytes()));
}

void RankRun::check_format_limits() const {
  const EngineCounters& c = whole_.counters();
  const bool triangles_only = job_.format == MeshFormat::stl || job_.mesh.triangulate;
  try {
    (void)mesh_file_head(job_.format, whole_mesh_, c.vertices,
                         triangles_only ? triangles_of(c) : c.polygons);
  } catch (const Error& error) {
    throw Error(job_.output, error.problem());
  }
  const bool ply = job_.format == MeshFormat::ply || job_.format == MeshFormat::ply_ascii;
  if (ply && c.vertices > PlyWriter::kVertexLimit.count)
    throw Error(job_.output, PlyWriter::kVertexLimit.problem());
}

void RankRun::join_summaries(const SlabSummary& mine) {
  summaries_ = world_.all_gather(mine);
  busy_ = world_.all_gather<char>(has_slices());
  for (int r = 0; r < world_.size(); ++r) {
    if (!busy_[r]) continue;  // a rank without slices (more ranks than slices)
    if (r < world_.rank()) before_.end(summaries_[r]);
    whole_.end(summaries_[r]);
  }
}

void RankRun::extract() {
  SlabSummary drawn;  // without a mesh: this step is the only run
  world_.step([&] {
    if (!has_slices()) return;
    const bool draw = picture_.has_value();
    if (!want_mesh()) {
      drawn = run_slab(engine_, nullptr, nullptr, false, draw);
      return;
    }
    MeshWriterOptions options = whole_mesh_;
    options.part = MeshWriterOptions::Part{before_.vertices_before()};
    options.sync = false;
    part_ = open_part_writer(options);
    SlabReplay replay(part_.get(), before_);
    try {
      run_slab(engine_, &part_->placement(), &replay, job_.normals, draw);
    } catch (...) {
      if (part_->error()) throw *part_->error();  // the writer refused: its error, not the stop
      throw;
    }
    part_->complete();
    // The count gave this rank's vertex numbers and the header's counts: a file that changed
    // between the passes must not give a mesh whose counts and indices disagree.
    const std::uint64_t counted = counted_.counters.vertices - counted_.counters.shared_vertices;
    const std::uint64_t written = part_->vertices_written() - before_.vertices_before();
    if (written != counted)
      throw Error(job_.input_label,
                  "changed while being read: slices " + std::to_string(span_.first) + " to " +
                      std::to_string(span_.end - 1) + " gave " + std::to_string(counted) +
                      " vertices, then " + std::to_string(written));
    if (placed_) {
      check_placed_part();
      return;
    }
    shape_.face_bytes = part_->part_face_bytes();
    shape_.vertex_bytes = part_->output_file()->bytes_written() - shape_.face_bytes;
    shape_.faces = part_->faces_written();
  });
  if (!want_mesh()) join_summaries(drawn);
}

void RankRun::write_together() {
  const auto write_start = Clock::now();
  if (want_mesh()) {
    std::string part_path;
    if (!placed_) {
      // The parts' sizes are known now; their records wait in part files.
      shapes_ = world_.all_gather(shape_);
      for (const PartShape& shape : shapes_) faces_ += shape.faces;
      world_.step([&] {
        head_ = mesh_file_head(job_.format, whole_mesh_, whole_.counters().vertices, faces_);
      });
      const std::string path =
          world_.broadcast(world_.rank() == 0 ? mesh_file_->temporary_path() : "");
      shared_file_.emplace(world_, path, job_.output);
      if (part_) part_path = part_->output_file()->temporary_path();
    }
    shared_file_->write(head_, shapes_, part_path);
    shared_file_->close(job_.sync);
    part_.reset();  // deletes this rank's temporary part, if it has one
  }
  if (picture_) {
    std::optional<PictureReduction> reduction;
    world_.step(
        [&] { reduction.emplace(world_, layer_.get(), job_.picture.width, job_.picture.height); });
    const int reduced = reduction->reduce();
    world_.step([&] {
      if (reduced != MPI_SUCCESS)
        throw Error("MPI", "compositing the picture failed: " + mpi_error_text(reduced));
      if (world_.rank() == 0) reduction->composite_into(*picture_, &report_.render);
    });
  }
  write_seconds_ = seconds_since(write_start);
}

void RankRun::publish() {
  report_.result.counters = whole_.counters();
  report_.result.workspace_bytes = engine_workspace_bytes(info_.width, info_.height, engine_);
  if (want_mesh()) {
    report_.format = mesh_format_name(job_.format);
    report_.faces_written = faces_;
  }
  PhaseTimes& times = report_.result.times;
  times.read_s = read_seconds_ + job_.source_open_s;
  times.write_s = write_seconds_;
  times.total_s = seconds_since(start_) + job_.source_open_s;
  times.extract_s = seconds_since(start_) - write_seconds_;
  report_.peak_memory_bytes = world_.max(peak_resident_bytes());
  world_.step([&] {
    if (world_.rank() != 0) return;
    std::vector<OutputFile*> sealed;
    if (mesh_file_) {
      mesh_file_->seal();
      sealed.push_back(&*mesh_file_);
    }
    if (picture_) {
      picture_->complete(info_.depth);
      if (picture_->image_file()) sealed.push_back(picture_->image_file());
    }
    if (stats_file_) {
      const std::string json = run_report_json(report_);
      stats_file_->write(json.data(), json.size());
      stats_file_->seal();
      sealed.push_back(&*stats_file_);
    }
    publish_together(sealed);
    if (!job_.quiet) print_run_summary(report_);
  });
}

}  // namespace

void run_distributed_mesh_job(SliceSource& source, const MeshJob& job, MpiWorld& world) {
  world.join();
  RankRun run(source, job, world);
  if (!run.prepare()) return;
  if (!job.output.empty()) run.count();
  run.extract();
  run.write_together();
  run.publish();
}

}  // namespace mvox
