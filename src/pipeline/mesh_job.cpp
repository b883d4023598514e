#include "pipeline/mesh_job.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include "error.h"
#include "labels/label_spool.h"
#include "message_line.h"
#include "picture/normal_window.h"
#include "picture/picture_layer.h"
#include "pipeline/peak_memory.h"
#include "pipeline/pipeline.h"
#include "pipeline/prefetching_source.h"
#include "pipeline/progress.h"
#include "pipeline/slab_extraction.h"
#include "pipeline/stopwatch.h"
#include "pipeline/termination.h"
#include "postprocess/edge_smoothing.h"
#include "read/copied_slices.h"
#include "write/buffered_writer.h"
#include "write/deferred_close.h"
#include "write/output_file.h"
#include "write/output_targets.h"
#include "write/slice_image_writer.h"

namespace mvox {

std::string grouped(std::uint64_t value) {
  std::string digits = std::to_string(value);
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(i, ",");
  return digits;
}

const char* surface_method_name(SurfaceMethod method) {
  return method == SurfaceMethod::cubes ? "cubes" : "voxels";
}

const char* engine_kind_name(EngineKind kind) {
  return kind == EngineKind::literal ? "literal" : "fast";
}

const char* surface_rule_name(SurfaceRule rule) {
  return rule == SurfaceRule::paper_table1 ? "paper-table1" : "merge-rules";
}

void print_run_summary(const RunReport& r) {
  const EngineCounters& c = r.result.counters;
  const PhaseTimes& t = r.result.times;
  const double voxels = double(r.volume.width) * r.volume.height * double(c.slices);
  const double mebibyte = 1 << 20;
  const std::string named = one_line(r.output.empty() ? r.image : r.output);
  if (r.method == "cubes") {
    std::fprintf(stderr, "%s: %s vertices, %s triangles (marching cubes)", named.c_str(),
                 grouped(c.vertices).c_str(), grouped(c.polygons).c_str());
  } else {
    std::fprintf(stderr, "%s: %s vertices, %s polygons (", named.c_str(),
                 grouped(c.vertices).c_str(), grouped(c.polygons).c_str());
    for (int size = 3; size <= kMaxPolygonVertices; ++size)
      std::fprintf(stderr, "%s%d-gons %s", size > 3 ? ", " : "", size,
                   grouped(c.polygons_by_size[size]).c_str());
    std::fprintf(stderr, ")%s", r.interpolated ? ", vertices interpolated" : "");
  }
  if (r.smooth_iterations > 0) {
    std::fprintf(stderr, ", smoothed %u times", r.smooth_iterations);
  }
  if (r.piece_rule)
    std::fprintf(stderr, ", %s of %s pieces kept (%s polygons)",
                 grouped(r.pieces.pieces_kept).c_str(), grouped(r.pieces.pieces).c_str(),
                 grouped(r.pieces.polygons_kept).c_str());
  if (r.decimation) {
    const DecimationCounts& d = r.result.decimation;
    std::fprintf(stderr, ", decimated to %s triangles (%.1f%% of %s) on %s vertices",
                 grouped(d.triangles_out).c_str(),
                 d.triangles_in ? 100.0 * double(d.triangles_out) / double(d.triangles_in) : 0.0,
                 grouped(d.triangles_in).c_str(), grouped(d.vertices_out).c_str());
  }
  // STL and --triangulate write triangles: say how many, and in which format.
  const std::uint64_t polygons_written = r.piece_rule ? r.pieces.polygons_kept : c.polygons;
  if (!r.output.empty() && r.faces_written != polygons_written)
    std::fprintf(stderr, ", written as %s triangles (%s)", grouped(r.faces_written).c_str(),
                 r.format.c_str());
  std::fprintf(stderr,
               "\n  from %ux%ux%llu %s voxels at threshold %g: read %.3f s, extract %.3f s "
               "(%.0f Mvoxel/s), write %.3f s, render %.3f s\n  peak memory %.1f MiB, of which "
               "%.1f MiB for this job (planned %.1f MiB; the rest is libraries)\n",
               r.volume.width, r.volume.height, static_cast<unsigned long long>(c.slices),
               sample_type_name(r.volume.type), r.threshold, t.read_s, t.extract_s,
               t.extract_s > 0 ? voxels / t.extract_s / 1e6 : 0.0, t.write_s, t.render_s,
               static_cast<double>(r.peak_memory_bytes) / (1 << 20),
               static_cast<double>(r.peak_memory_bytes -
                                   std::min(r.peak_memory_bytes, r.start_memory_bytes)) /
                   mebibyte,
               static_cast<double>(r.memory_plan.job_bytes()) / mebibyte);
  if (!r.image.empty())
    std::fprintf(stderr,
                 "  picture %s: %s triangles drawn, %s hidden or between pixels, %s facing "
                 "away\n",
                 one_line(r.image).c_str(), grouped(r.render.triangles_drawn).c_str(),
                 grouped(r.render.triangles_hidden).c_str(),
                 grouped(r.render.triangles_culled).c_str());
}

void print_dry_run(const RunReport& r, const MeshJob& job, const MemoryPlan& plan) {
  std::printf("%s extract --dry-run: %s, %ux%ux%u %s voxels, threshold %g\n", message_program(),
              r.input.c_str(), r.volume.width, r.volume.height, r.volume.depth,
              sample_type_name(r.volume.type), r.threshold);
  if (!job.output.empty())
    std::printf("  mesh: %s (%s)\n", job.output.c_str(), mesh_format_name(job.format));
  if (!job.picture.image_path.empty())
    std::printf("  picture: %s (%ux%u)\n", job.picture.image_path.c_str(), job.picture.width,
                job.picture.height);
  if (!job.picture.frames_dir.empty())
    std::printf("  frames: %s, every %u slices\n", job.picture.frames_dir.c_str(),
                job.picture.every);
  if (!job.stats_path.empty()) std::printf("  report: %s\n", job.stats_path.c_str());
  std::printf("memory (fixed for the whole run, whatever the number of slices):\n%s",
              memory_plan_text(plan, job.budget).c_str());
  std::printf("nothing read but headers, nothing written\n");
  std::fflush(stdout);
}

const char* why_one_engine(const MeshJob& job) {
  if (job.smooth_iterations > 0)
    return "--smooth needs the layers on both sides of a slab's boundary";
  if (job.decimation) return "--decimate needs the layers on both sides of a slab's boundary";
  if (job.pieces.active())
    return job.pieces.largest ? "--largest keeps the mesh of one engine until its end"
                              : "--min-faces keeps the mesh of one engine until its end";
  return nullptr;
}

unsigned slab_threads(const SliceSource& source, const MeshJob& job) {
  const VolumeInfo& info = source.info();
  unsigned threads = job.threads;
  if (threads == 0) {
    const std::uint64_t bytes =
        std::uint64_t{info.width} * info.height * info.depth * sample_bytes(info.type);
    threads = bytes >= kAutoSlabVolumeBytes ? std::max(1u, std::thread::hardware_concurrency()) : 1;
  }
  if (threads <= 1 || why_one_engine(job)) return 1;
  const std::uint32_t slabs = slab_count(info, job.slab_slices);
  // At most one worker per slab (run_slab_pipeline takes no more).
  return slabs >= 2 ? std::min(threads, slabs) : 1;
}

bool one_engine_helpers(const SliceSource& source, const MeshJob& job) {
  if (!job.read_ahead) return false;
  if (job.threads != 0) return true;  // asked for
  const VolumeInfo& info = source.info();
  const std::uint64_t bytes =
      std::uint64_t{info.width} * info.height * info.depth * sample_bytes(info.type);
  const auto* copied = dynamic_cast<const CopiedSlices*>(&source);
  return bytes >= kAutoSlabVolumeBytes || !copied || !copied->slices_are_copied();
}

namespace {

// Whether the writers may write on a thread of their own (BufferedWriter) in a run of `threads`
// slab workers, or of one engine (threads 1). Slab workers on every core leave none for a
// writing thread beside them: each worker then writes on its own thread when its turn comes, as
// --threads 1 does. Two workers on two cores were 4-6% faster so (medians of 21 interleaved
// rounds, raw 256x256x1024 to PLY and STL). One engine writes in the background only when its
// helper threads pay (one_engine_helpers).
bool writes_in_background(const SliceSource& source, const MeshJob& job, unsigned threads) {
  const bool every_core =
      threads > 1 && threads >= std::max(1u, std::thread::hardware_concurrency());
  return BufferedWriter::background_writes_allowed() && !every_core &&
         (threads > 1 || one_engine_helpers(source, job));
}

}  // namespace

MemoryPlan plan_job_memory(const SliceSource& source, const MeshJob& job,
                           const EngineOptions& engine) {
  const VolumeInfo& info = source.info();
  const std::uint64_t slice = std::uint64_t{info.width} * info.height * sample_bytes(info.type);
  const bool picture = job.picture.wanted();
  MemoryPlan plan;
  plan.process_bytes = current_resident_bytes();
  const unsigned threads = slab_threads(source, job);
  std::size_t slab_item = 0;
  std::uint64_t one_more = 0;  // one chunk more on every worker
  if (threads > 1) {
    SlabOptions slabs;
    slabs.threads = threads;
    slabs.slab_slices = job.slab_slices;
    slabs.normals = job.normals;
    slabs.smooth_picture = picture && job.picture.smooth;
    if (own_range_reader(source)) slabs.reader_bytes = source.working_bytes();
    if (!job.output.empty()) {
      slabs.formatted_bytes_per_polygon = formatted_bytes_per_polygon(job.format);
      slabs.formatted_bytes_per_vertex = formatted_bytes_per_vertex(job.format, job.normals);
    }
    // The output recorded ahead of the writer, planned first with the chunks every worker
    // starts with; once the rest of the plan is known, with as many more as the budget leaves
    // room for (below).
    slabs.most_chunks = kChunksPerWorker;
    one_more = slab_chunk_bytes(engine, slabs);
    const std::uint64_t chunks = kChunksPerWorker * one_more;
    plan.add(std::to_string(threads) + " slab workers (workspace, slices, window)",
             slab_pipeline_bytes(info, engine, slabs) - chunks);
    slab_item = plan.items.size();
    plan.add("", chunks);
    if (picture) {
      // And the picture's own slab numbers, once the layers are composited; the copies of its
      // pixels that frames (one per worker) and a live window show (slab_picture_follower.h).
      const std::uint64_t pixels = std::uint64_t{job.picture.width} * job.picture.height;
      plan.add(std::to_string(threads) + " picture layers (z-buffer, slab of each pixel)",
               threads * PictureLayer::bytes(job.picture.width, job.picture.height) + pixels * 4 +
                   (job.picture.frames_dir.empty() ? 0 : threads * pixels) +
                   (job.picture.show ? pixels : 0));
    }
    plan.add("reader (slice and decoder buffers)", source.working_bytes());
  } else {
    plan.add("engine workspace", engine_workspace_bytes(info.width, info.height, engine));
    plan.add("reader (slice and decoder buffers)", source.working_bytes());
    if (one_engine_helpers(source, job))
      plan.add("reading ahead (2 batches)", PrefetchingSource::buffer_bytes(info));
    if (job.normals || (picture && job.picture.smooth)) {
      const std::uint32_t slots = slice_window_slots(smooth_window_depth(job.smooth_iterations));
      plan.add("slice window (" + std::to_string(slots) + " slices)", slots * slice);
    }
    if (job.decimation)
      plan.add("decimation (" + std::to_string(LayerDecimation::kLayersPerPass + 1) +
                   " layers of triangles held)",
               LayerDecimation::layer_bytes(info.width, info.height) *
                   (LayerDecimation::kLayersPerPass + 1));
    if (job.smooth_iterations > 0)
      plan.add("smoothing (" + std::to_string(job.smooth_iterations + 3) + " layers held)",
               EdgeSmoothing::layer_bytes(info.width, info.height) * (job.smooth_iterations + 3));
    if (job.pieces.active())
      plan.add("connected pieces (vertex ring and spool buffers; the pieces themselves grow)",
               piece_filter_bytes(std::uint64_t{info.width} * info.height) +
                   2 * BufferedWriter::kBufferBytes);
  }
  if (picture) {
    // The z-buffer, and an encoded picture or frame: at most about one byte a pixel for the
    // 8-bit picture, twice to allow for the encoder's own copy.
    const std::uint64_t pixels = std::uint64_t{job.picture.width} * job.picture.height;
    plan.add("picture (z-buffer, encoding)",
             zbuffer_workspace_bytes(job.picture.width, job.picture.height) + 2 * pixels);
  }
  if (!job.output.empty())
    plan.add("mesh writer buffers",
             mesh_writer_working_bytes(job.format, writes_in_background(source, job, threads)));
  if (threads > 1) {
    // Workers ahead of the writer may hold up to about a slab's output rather than wait for
    // their turn (most_chunks_per_worker), in at most half the room the budget leaves (the
    // default budget is the machine's memory, not what is free of it): a run that fits with the
    // first four chunks a worker is never refused for the others. Without a mesh the chunks
    // carry only how each slab ended, and a worker takes no more (run_slab_pipeline).
    unsigned most = job.output.empty()
                        ? kChunksPerWorker
                        : most_chunks_per_worker(info, slab_slices_of(info, job.slab_slices));
    if (job.budget.bytes > 0 && one_more > 0) {
      const std::uint64_t total = plan.total_bytes();
      const std::uint64_t room = job.budget.bytes > total ? job.budget.bytes - total : 0;
      most = static_cast<unsigned>(
          std::min<std::uint64_t>(most, kChunksPerWorker + room / 2 / one_more));
    }
    plan.slab_chunks = most;
    const std::string chunks =
        most > kChunksPerWorker ? std::to_string(kChunksPerWorker) + " to " + std::to_string(most)
                                : std::to_string(most);
    plan.items[slab_item] = {
        job.output.empty() ? "chunks that carry how each slab ended (" + chunks + " a worker)"
                           : "output recorded ahead of the writer (" + chunks + " chunks a worker)",
        most * one_more};
  }
  return plan;
}

RunReport start_run_report(const SliceSource& source, const MeshJob& job) {
  RunReport report;
  report.start_memory_bytes = current_resident_bytes();
  report.input = job.input_label;
  report.output = job.output;
  report.image = job.picture.image_path;
  report.volume = source.info();
  // The report gives the placement the mesh and picture were made with (--spacing wins).
  const WorldTransform& placement = job.mesh.transform;
  for (int axis = 0; axis < 3; ++axis) {
    report.volume.spacing[axis] = placement.spacing[axis];
    report.volume.origin[axis] = placement.origin[axis];
    for (int i = 0; i < 3; ++i) report.volume.axes[axis][i] = placement.axes[axis][i];
  }
  report.threshold = job.threshold;
  report.method = surface_method_name(job.engine.method);
  report.engine = engine_kind_name(job.engine.kind);
  report.surface = surface_rule_name(job.engine.rule);
  report.interpolated = job.engine.method == SurfaceMethod::cubes || job.engine.interpolate;
  report.smooth_iterations = job.smooth_iterations;
  if (job.decimation) report.decimation = *job.decimation;
  return report;
}

void check_job_outputs(const MeshJob& job, std::uint32_t depth) {
  const bool want_mesh = !job.output.empty();
  if (!want_mesh && !job.picture.wanted())
    throw UsageError(job.input_label,
                     "nothing to write: give -o mesh.ply, --image picture.png or both");
  if (job.normals && !want_mesh) throw UsageError("--normals", "needs a mesh output (-o)");
  if (job.mesh.triangulate && !want_mesh)
    throw UsageError("--triangulate", "needs a mesh output (-o)");
  // No output may land on an input or on another output: checked before any is created.
  std::vector<OutputTarget> targets;
  if (want_mesh) targets.push_back({job.output, "-o", "the mesh"});
  if (!job.picture.image_path.empty())
    targets.push_back({job.picture.image_path, "--image", "the picture"});
  if (!job.stats_path.empty()) targets.push_back({job.stats_path, "--stats", "the report"});
  std::optional<FramesTarget> frames;
  if (!job.picture.frames_dir.empty())
    frames = FramesTarget{job.picture.frames_dir, job.picture.every, depth};
  check_output_targets(targets, frames, job.input_files, InputFiles::found);
}

RunReport run_mesh_job(SliceSource& source, const MeshJob& job) {
  RunReport report = start_run_report(source, job);
  const WorldTransform& placement = job.mesh.transform;
  const bool want_mesh = !job.output.empty();
  const bool want_picture = job.picture.wanted();
  check_job_outputs(job, report.volume.depth);

  // The memory the run will take, known before anything is allocated: a run that cannot fit,
  // or slices too large to extract at all, are refused now rather than after gigabytes.
  EngineOptions engine = job.engine;
  engine.polygon_geometry =
      want_picture || (want_mesh && mesh_writer_needs_geometry(job.format, job.mesh));
  const VolumeInfo& info = report.volume;
  if (engine_workspace_bytes(info.width, info.height, engine) == 0)
    throw Error(job.input_label, "slices of " + std::to_string(info.width) + "x" +
                                     std::to_string(info.height) +
                                     " voxels are too large to extract");
  // A picture of a type mvox does not write itself loads OpenCV's codecs now, so that they count
  // as library memory, not the run's. (Frames are always PNG.)
  if (!job.picture.image_path.empty()) initialize_image_codecs(job.picture.image_path);
  report.memory_plan = plan_job_memory(source, job, engine);
  // The job's own memory is measured from here, as the plan's is.
  report.start_memory_bytes = report.memory_plan.process_bytes;
  report.memory_budget = job.budget;
  check_memory_budget(report.memory_plan, job.budget, job.input_label);
  if (job.dry_run) {
    print_dry_run(report, job, report.memory_plan);
    return report;
  }

  // Every output is created before extraction starts, so a bad path fails at once, not after a
  // long run; they appear together, and only when everything has succeeded.
  const unsigned threads = slab_threads(source, job);
  // Unless the run must take one thread: a large scratch file, once copied, is closed on a
  // thread of its own, waited for when the run ends, by an exception too (deferred_close.h).
  const DeferredCloses deferred_closes(BufferedWriter::background_writes_allowed());
  struct BackgroundWrites {
    bool before = BufferedWriter::background_writes_allowed();
    explicit BackgroundWrites(bool allowed) { BufferedWriter::allow_background_writes(allowed); }
    ~BackgroundWrites() { BufferedWriter::allow_background_writes(before); }
  } background_writes(writes_in_background(source, job, threads));
  std::optional<NormalWindow> normal_window;
  if (threads == 1 && (job.normals || (want_picture && job.picture.smooth)))
    normal_window.emplace(report.volume, placement.spacing, job.input_label,
                          smooth_window_depth(job.smooth_iterations));
  const VertexNormals* normals = normal_window ? &normal_window->normals() : nullptr;
  std::unique_ptr<MeshWriter> writer;
  if (want_mesh) {
    MeshWriterOptions mesh = job.mesh;
    mesh.normals = job.normals ? normals : nullptr;
    mesh.normals_given = job.normals && threads > 1;  // each slab computes its own
    mesh.sync = mesh.sync || job.sync;
    writer = open_mesh_writer(job.output, job.format, mesh);
    // STL and --triangulate need each polygon's positions.
    if (writer->needs_polygon_geometry()) engine.polygon_geometry = true;
  }
  std::optional<SurfacePicture> picture;
  if (want_picture) {
    PictureOptions picture_options = job.picture;
    picture_options.sync = picture_options.sync || job.sync;
    picture.emplace(report.volume, placement.spacing, placement.origin, normals, picture_options);
  }
  std::optional<OutputFile> stats_file;
  if (!job.stats_path.empty()) stats_file.emplace(job.stats_path, job.sync);

  // --largest / --min-faces: the mesh goes to a spool first, and its kept pieces to the writer
  // after extraction.
  std::optional<LabelSpool> spool;
  // Beside the output, or in the temporary directory for standard output and devices.
  const std::string spool_directory =
      writer && writer->output_file() ? writer->output_file()->scratch_directory() : ".";
  if (writer && job.pieces.active()) spool.emplace(spool_directory, job.output);
  // Threads asked for and not used are said once, not silently dropped; after every output
  // is created, so that a refusal before the run stays one line.
  if (job.threads > 1 && !job.quiet)
    if (const char* why = why_one_engine(job))
      print_message("note", "--threads " + std::to_string(job.threads) + ": " + why +
                                "; one engine extracts");
  PipelineSinks sinks;
  if (writer) sinks.mesh = spool ? &spool->session(1) : &*writer;
  if (picture) sinks.render = &picture->sink();
  if (normal_window) sinks.window = &normal_window->window();
  sinks.smooth_iterations = job.smooth_iterations;
  if (job.decimation) sinks.decimation = &*job.decimation;
  {
    ProgressLine progress("extracting", report.volume.depth,
                          !job.quiet && ProgressLine::stderr_is_terminal());
    // Called after every slice, so only when it has something to do: a call and its timing
    // cost more than a slice of a few voxels takes to extract.
    ProgressCallback after_slice;
    if (progress.enabled() || (picture && picture->follows_slices()))
      after_slice = [&](std::uint32_t done) {
        progress.update(done);
        if (picture) picture->after_slice(done);
      };
    if (threads > 1) {
      SlabOptions slabs;
      slabs.threads = threads;
      slabs.slab_slices = job.slab_slices;
      slabs.normals = job.normals;
      slabs.spacing = placement.spacing;
      slabs.picture = picture ? &*picture : nullptr;
      slabs.smooth_picture = picture && job.picture.smooth;
      slabs.most_chunks = report.memory_plan.slab_chunks;  // as the budget allows
      // Frames and the window follow the workers' layers (slab_picture_follower.h), not slices.
      ProgressCallback slabs_done;
      if (progress.enabled()) slabs_done = [&](std::uint32_t done) { progress.update(done); };
      report.result = run_slab_pipeline(source, job.threshold, engine, writer.get(), slabs,
                                        job.input_label, slabs_done);
    } else if (!one_engine_helpers(source, job)) {
      report.result =
          run_pipeline(source, job.threshold, engine, sinks, job.input_label, after_slice);
    } else {
      // Reading overlaps extraction from here on; the read time reported is the time spent
      // waiting for a slice.
      PrefetchingSource prefetched(source);
      report.result = run_pipeline(prefetched, job.threshold, engine, sinks, job.input_label,
                                   after_slice, [&] { return prefetched.seconds_waiting(); });
    }
  }
  if (picture) {
    // Frames and the window's updates are rendering, not extraction: one engine made them
    // between slices, slab workers between slabs (the time of each summed, as their writing
    // is; slab_picture_follower.h).
    const double following = picture->seconds_following();
    report.result.times.render_s += following;
    report.result.times.extract_s = std::max(0.0, report.result.times.extract_s - following);
  }
  if (report.result.status == Status::sink_refused && spool && spool->error())
    throw *spool->error();
  if (report.result.status == Status::sink_refused && writer && writer->error())
    throw *writer->error();
  if (report.result.status != Status::ok)
    throw Error(job.input_label,
                std::string("extraction failed: ") + status_message(report.result.status));

  const auto write_start = Clock::now();
  if (spool) {
    report.piece_rule = job.pieces;
    const Status status = write_kept_pieces(*spool, 1, std::uint64_t{info.width} * info.height,
                                            job.pieces, spool_directory, *writer, &report.pieces);
    if (status == Status::sink_refused && writer->error()) throw *writer->error();
    if (status != Status::ok)
      throw Error(job.output, std::string("writing failed: ") + status_message(status));
  }
  if (writer) {
    writer->complete();
    report.format = mesh_format_name(job.format);
    report.faces_written = writer->faces_written();
  }
  const double write_s = seconds_since(write_start);
  const auto render_start = Clock::now();
  if (picture) {
    picture->complete(static_cast<std::uint32_t>(report.result.counters.slices));
    report.render = picture->renderer().counters();
  }
  const double render_s = seconds_since(render_start);
  report.result.times.write_s += write_s;
  report.result.times.render_s += render_s;
  report.result.times.read_s += job.source_open_s;
  report.result.times.total_s += write_s + render_s + job.source_open_s;
  report.peak_memory_bytes = peak_resident_bytes();

  if (stats_file) {
    const std::string json = run_report_json(report);
    stats_file->write(json.data(), json.size());
    stats_file->seal();
  }
  // All or none: every target is checked before the first rename, and a rename that still
  // fails brings the files already replaced back (publish_together).
  std::vector<OutputFile*> sealed;
  if (writer) sealed.push_back(writer->output_file());
  if (picture && picture->image_file()) sealed.push_back(picture->image_file());
  if (stats_file) sealed.push_back(&*stats_file);
  publish_together(sealed);  // while the scratch files' pages are freed (deferred_closes)
  if (!job.quiet) print_run_summary(report);
  return report;
}

}  // namespace mvox
