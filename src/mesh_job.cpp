#include "mesh_job.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#include "error.h"
#include "output_file.h"
#include "peak_memory.h"
#include "pipeline.h"
#include "progress.h"

namespace mvox {

std::string grouped(std::uint64_t value) {
  std::string digits = std::to_string(value);
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(i, ",");
  return digits;
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
  std::fprintf(stderr, "%s: %s vertices, %s polygons (", r.output.c_str(),
               grouped(c.vertices).c_str(), grouped(c.polygons).c_str());
  for (int size = 3; size <= kMaxPolygonVertices; ++size)
    std::fprintf(stderr, "%s%d-gons %s", size > 3 ? ", " : "", size,
                 grouped(c.polygons_by_size[size]).c_str());
  std::fprintf(
      stderr,
      ")\n  from %ux%ux%llu %s voxels at threshold %g: read %.3f s, extract %.3f s "
      "(%.0f Mvoxel/s), write %.3f s\n  peak memory %.1f MiB, of which %.1f MiB for this job "
      "(the rest is libraries)\n",
      r.volume.width, r.volume.height, static_cast<unsigned long long>(c.slices),
      sample_type_name(r.volume.type), r.threshold, t.read_s, t.extract_s,
      t.extract_s > 0 ? voxels / t.extract_s / 1e6 : 0.0, t.write_s,
      static_cast<double>(r.peak_memory_bytes) / (1 << 20),
      static_cast<double>(r.peak_memory_bytes -
                          std::min(r.peak_memory_bytes, r.start_memory_bytes)) /
          (1 << 20));
}

}  // namespace

RunReport run_mesh_job(SliceSource& source, const MeshJob& job) {
  RunReport report;
  report.start_memory_bytes = current_resident_bytes();
  report.input = job.input_label;
  report.output = job.output;
  report.volume = source.info();
  report.threshold = job.threshold;
  report.method = "voxels";
  report.engine = engine_kind_name(job.engine.kind);
  report.surface = surface_rule_name(job.engine.rule);

  // Every output is created before extraction starts, so a bad path fails at once, not after a
  // long run; they appear together, and only when everything has succeeded.
  if (!job.stats_path.empty() && job.stats_path == job.output)
    throw Error("--stats", "'" + job.stats_path + "' is also the mesh output");
  PlyWriter writer(job.output, job.ply);
  std::optional<OutputFile> stats_file;
  if (!job.stats_path.empty()) stats_file.emplace(job.stats_path);
  {
    ProgressLine progress("extracting", report.volume.depth,
                          !job.quiet && ProgressLine::stderr_is_terminal());
    report.result = run_pipeline(source, job.threshold, job.engine, writer, job.input_label,
                                 [&progress](std::uint32_t done) { progress.update(done); });
  }
  if (report.result.status == Status::sink_refused && writer.error()) throw *writer.error();
  if (report.result.status != Status::ok)
    throw Error(job.input_label,
                std::string("extraction failed: ") + status_message(report.result.status));

  const auto finish_start = std::chrono::steady_clock::now();
  writer.complete();
  const double finish_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - finish_start).count();
  report.result.times.write_s += finish_s;
  report.result.times.read_s += job.source_open_s;
  report.result.times.total_s += finish_s + job.source_open_s;
  report.peak_memory_bytes = peak_resident_bytes();

  if (stats_file) {
    const std::string json = run_report_json(report);
    stats_file->write(json.data(), json.size());
    stats_file->seal();
  }
  writer.publish();
  if (stats_file) stats_file->publish();
  if (!job.quiet) print_summary(report);
  return report;
}

}  // namespace mvox
