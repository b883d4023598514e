#include "mesh_job.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "error.h"
#include "normal_window.h"
#include "output_file.h"
#include "peak_memory.h"
#include "pipeline.h"
#include "prefetching_source.h"
#include "progress.h"
#include "termination.h"

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

namespace {

void print_summary(const RunReport& r) {
  const EngineCounters& c = r.result.counters;
  const PhaseTimes& t = r.result.times;
  const double voxels = double(r.volume.width) * r.volume.height * double(c.slices);
  const std::string& named = r.output.empty() ? r.image : r.output;
  if (r.method == "cubes") {
    std::fprintf(stderr, "%s: %s vertices, %s triangles (marching cubes)", named.c_str(),
                 grouped(c.vertices).c_str(), grouped(c.polygons).c_str());
  } else {
    std::fprintf(stderr, "%s: %s vertices, %s polygons (", named.c_str(),
                 grouped(c.vertices).c_str(), grouped(c.polygons).c_str());
    for (int size = 3; size <= kMaxPolygonVertices; ++size)
      std::fprintf(stderr, "%s%d-gons %s", size > 3 ? ", " : "", size,
                   grouped(c.polygons_by_size[size]).c_str());
    std::fprintf(stderr, ")");
  }
  // STL and --triangulate write triangles: say how many, and in which format.
  if (!r.output.empty() && r.faces_written != c.polygons)
    std::fprintf(stderr, ", written as %s triangles (%s)", grouped(r.faces_written).c_str(),
                 r.format.c_str());
  std::fprintf(stderr,
               "\n  from %ux%ux%llu %s voxels at threshold %g: read %.3f s, extract %.3f s "
               "(%.0f Mvoxel/s), write %.3f s, render %.3f s\n  peak memory %.1f MiB, of which "
               "%.1f MiB for this job "
               "(the rest is libraries)\n",
               r.volume.width, r.volume.height, static_cast<unsigned long long>(c.slices),
               sample_type_name(r.volume.type), r.threshold, t.read_s, t.extract_s,
               t.extract_s > 0 ? voxels / t.extract_s / 1e6 : 0.0, t.write_s, t.render_s,
               static_cast<double>(r.peak_memory_bytes) / (1 << 20),
               static_cast<double>(r.peak_memory_bytes -
                                   std::min(r.peak_memory_bytes, r.start_memory_bytes)) /
                   (1 << 20));
  if (!r.image.empty())
    std::fprintf(stderr,
                 "  picture %s: %s triangles drawn, %s hidden or between pixels, %s facing "
                 "away\n",
                 r.image.c_str(), grouped(r.render.triangles_drawn).c_str(),
                 grouped(r.render.triangles_hidden).c_str(),
                 grouped(r.render.triangles_culled).c_str());
}

}  // namespace

RunReport run_mesh_job(SliceSource& source, const MeshJob& job) {
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

  const bool want_mesh = !job.output.empty();
  const bool want_picture = job.picture.wanted();
  if (!want_mesh && !want_picture)
    throw Error(job.input_label, "nothing to write: give -o mesh.ply, --image picture.png or both");
  if (job.normals && !want_mesh) throw Error("--normals", "needs a mesh output (-o)");
  if (job.mesh.triangulate && !want_mesh) throw Error("--triangulate", "needs a mesh output (-o)");
  // Two outputs on one path would overwrite each other when they appear.
  const std::string* paths[] = {&job.output, &job.picture.image_path, &job.stats_path};
  const char* names[] = {"the mesh output", "the image", "the --stats report"};
  for (int i = 0; i < 3; ++i)
    for (int k = i + 1; k < 3; ++k)
      if (!paths[i]->empty() && *paths[i] == *paths[k] && *paths[i] != "-")
        throw Error(*paths[k], std::string("is both ") + names[i] + " and " + names[k]);

  // Every output is created before extraction starts, so a bad path fails at once, not after a
  // long run; they appear together, and only when everything has succeeded.
  std::optional<NormalWindow> normal_window;
  if (job.normals || (want_picture && job.picture.smooth))
    normal_window.emplace(report.volume, placement.spacing, job.input_label);
  const VertexNormals* normals = normal_window ? &normal_window->normals() : nullptr;
  std::unique_ptr<MeshWriter> writer;
  EngineOptions engine = job.engine;
  if (want_mesh) {
    MeshWriterOptions mesh = job.mesh;
    mesh.normals = job.normals ? normals : nullptr;
    writer = open_mesh_writer(job.output, job.format, mesh);
    // STL and --triangulate need each polygon's positions.
    if (writer->needs_polygon_geometry()) engine.polygon_geometry = true;
  }
  std::optional<SurfacePicture> picture;
  if (want_picture)
    picture.emplace(report.volume, placement.spacing, placement.origin, normals, job.picture);
  std::optional<OutputFile> stats_file;
  if (!job.stats_path.empty()) stats_file.emplace(job.stats_path);

  PipelineSinks sinks;
  if (writer) sinks.mesh = &*writer;
  if (picture) sinks.render = &picture->sink();
  if (normal_window) sinks.window = &normal_window->window();
  {
    ProgressLine progress("extracting", report.volume.depth,
                          !job.quiet && ProgressLine::stderr_is_terminal());
    // Called after every slice, so only when it has something to do: a call and its timing
    // cost more than a slice of a few voxels takes to extract.
    SliceProgress after_slice;
    if (progress.enabled() || (picture && picture->follows_slices()))
      after_slice = [&](std::uint32_t done) {
        progress.update(done);
        if (picture) picture->after_slice(done);
      };
    // Reading overlaps extraction from here on; the read time reported is the time spent
    // waiting for a slice.
    PrefetchingSource prefetched(source);
    report.result = run_pipeline(prefetched, job.threshold, engine, sinks, job.input_label,
                                 after_slice, [&] { return prefetched.seconds_waiting(); });
  }
  if (picture) {
    // Frames and the window's updates happened between slices: rendering, not extraction.
    const double following = picture->seconds_following();
    report.result.times.render_s += following;
    report.result.times.extract_s -= following;
  }
  if (report.result.status == Status::sink_refused && writer && writer->error())
    throw *writer->error();
  if (report.result.status != Status::ok)
    throw Error(job.input_label,
                std::string("extraction failed: ") + status_message(report.result.status));

  using Clock = std::chrono::steady_clock;
  auto seconds_since = [](Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  const auto write_start = Clock::now();
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
  {
    // An interrupt now waits for the renames, so that the outputs appear all or none.
    InterruptsDeferred publishing;
    if (writer) writer->publish();
    if (picture) picture->publish();
    if (stats_file) stats_file->publish();
  }
  if (!job.quiet) print_summary(report);
  return report;
}

}  // namespace mvox
