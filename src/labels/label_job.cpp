#include "labels/label_job.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include "error.h"
#include "labels/label_spool.h"
#include "mvox/workspace_buffer.h"
#include "pipeline/mesh_job.h"
#include "pipeline/peak_memory.h"
#include "pipeline/progress.h"
#include "pipeline/stopwatch.h"
#include "write/output_file.h"
#include "write/output_targets.h"
#include "write/stats_json.h"

namespace mvox {
namespace {

// An engine extracting one label while the label is in the slices, with the mask it is fed.
// Kept for the next label that appears once its own is gone: workspaces are allocated once.
struct LabelEngine {
  LabelEngine(std::size_t workspace_bytes, std::size_t pixels)
      : workspace(workspace_bytes), mask(pixels) {}
  WorkspaceBuffer workspace;
  std::vector<std::uint8_t> mask;
  Engine engine;
  std::uint32_t label = 0;
};

SliceView mask_view(const std::vector<std::uint8_t>& mask, std::uint32_t width,
                    std::uint32_t height) {
  SliceView view;
  view.samples = mask.data();
  view.width = width;
  view.height = height;
  view.row_stride_bytes = width;
  view.type = SampleType::u8;
  return view;
}

void check_status(Status status, const LabelSpool& spool, const std::string& input_label) {
  if (status == Status::ok) return;
  if (status == Status::sink_refused && spool.error()) throw *spool.error();
  throw Error(input_label, std::string("extraction failed: ") + status_message(status));
}

}  // namespace

std::string label_file_name(const std::string& pattern, std::uint32_t label) {
  std::string name = pattern;
  const std::string number = std::to_string(label);
  for (std::size_t at = name.find("{label}"); at != std::string::npos;
       at = name.find("{label}", at + number.size()))
    name.replace(at, 7, number);
  return name;
}

LabelReport run_label_job(SliceSource& source, const LabelJob& job) {
  const auto start = Clock::now();
  LabelReport report;
  report.input = job.input_label;
  report.volume = source.info();
  report.pieces = job.pieces.active();
  report.start_memory_bytes = current_resident_bytes();
  const VolumeInfo& info = report.volume;
  const std::size_t pixels = std::size_t{info.width} * info.height;

  EngineOptions engine_options = job.engine;
  engine_options.polygon_geometry = mesh_writer_needs_geometry(job.format, job.mesh);
  // Small batches: an atlas keeps a hundred engines at once, and the spool takes any batch size
  // (the surface is the same; only how it is cut into calls changes).
  engine_options.vertices_per_batch = std::min<std::uint32_t>(engine_options.vertices_per_batch, 512);
  engine_options.polygons_per_batch = std::min<std::uint32_t>(engine_options.polygons_per_batch, 512);
  const std::size_t workspace_bytes =
      engine_workspace_bytes(info.width, info.height, engine_options);
  if (workspace_bytes == 0)
    throw Error(job.input_label, "slices of " + std::to_string(info.width) + "x" +
                                     std::to_string(info.height) +
                                     " voxels are too large to extract");
  report.engine_bytes = workspace_bytes + pixels;

  // The spool lives where the meshes will: the same file system, which must have the room.
  const std::filesystem::path first_file(label_file_name(job.output_pattern, 1));
  const std::string directory =
      first_file.has_parent_path() ? first_file.parent_path().string() : ".";
  LabelSpool spool(directory, job.output_pattern);

  LabelSlices slices(job.labels);
  const std::vector<std::uint8_t> empty_slice(pixels, 0);
  std::map<std::uint32_t, std::unique_ptr<LabelEngine>> running;  // by label
  std::vector<std::unique_ptr<LabelEngine>> idle;
  std::vector<std::uint32_t> fed;  // the labels fed this slice: present now or in the last one
  std::vector<std::uint8_t*> masks;
  std::optional<ProgressLine> progress;
  progress.emplace("extracting labels", info.depth,
                   !job.quiet && ProgressLine::stderr_is_terminal());

  double read_s = 0;
  for (std::uint32_t z = 0; z < info.depth; ++z) {
    const auto read_start = Clock::now();
    SliceView slice;
    if (!source.next_slice(&slice))
      throw Error(job.input_label, "the input ended after " + std::to_string(z) + " of " +
                                       std::to_string(info.depth) + " slices");
    read_s += seconds_since(read_start);

    const std::vector<std::uint32_t>& present = slices.labels_in(slice);
    // Labels that appear here get an engine, started after an empty slice z - 1.
    for (const std::uint32_t label : present) {
      if (running.count(label)) continue;
      std::unique_ptr<LabelEngine> started;
      if (!idle.empty()) {
        started = std::move(idle.back());
        idle.pop_back();
      } else {
        started = std::make_unique<LabelEngine>(workspace_bytes, pixels);
      }
      started->label = label;
      PolygonSink& sink = spool.session(label);
      check_status(started->engine.init(started->workspace.data(), started->workspace.bytes(),
                                        info.width, info.height, 1.0, engine_options, &sink),
                   spool, job.input_label);
      if (z > 0)
        check_status(started->engine.begin_slab(mask_view(empty_slice, info.width, info.height), z),
                     spool, job.input_label);
      running.emplace(label, std::move(started));
    }
    report.most_engines = std::max(report.most_engines, static_cast<std::uint32_t>(running.size()));
    // Every running engine takes this slice: its label's mask, empty where the label has gone.
    fed.clear();
    masks.clear();
    for (auto& [label, engine] : running) {
      fed.push_back(label);
      masks.push_back(engine->mask.data());
    }
    slices.fill_masks(slice, fed, masks);
    for (auto& [label, engine] : running)
      check_status(engine->engine.push_slice(mask_view(engine->mask, info.width, info.height)),
                   spool, job.input_label);
    // Labels absent from this slice are closed: their surface ends below it.
    for (auto it = running.begin(); it != running.end();) {
      if (std::binary_search(present.begin(), present.end(), it->first)) {
        ++it;
        continue;
      }
      check_status(it->second->engine.finish(), spool, job.input_label);
      idle.push_back(std::move(it->second));
      it = running.erase(it);
    }
    progress->update(z + 1);
  }
  for (auto& [label, engine] : running) check_status(engine->engine.finish(), spool, job.input_label);
  running.clear();
  idle.clear();
  progress.reset();
  report.extract_s = seconds_since(start) - read_s;
  report.read_s = read_s;
  report.spool_bytes = spool.bytes_written();
  report.spool_index_bytes = spool.index_bytes();

  // The files, one label at a time, checked against the inputs and each other first.
  const auto write_start = Clock::now();
  std::vector<OutputTarget> targets;
  for (const auto& [label, counts] : spool.labels())
    targets.push_back({label_file_name(job.output_pattern, label), "-o",
                       "the mesh of label " + std::to_string(label)});
  if (!job.stats_path.empty()) targets.push_back({job.stats_path, "--stats", "the report"});
  check_output_targets(targets, std::nullopt, job.input_files, InputFiles::found);
  std::vector<std::unique_ptr<MeshWriter>> writers;
  for (const auto& [label, counts] : spool.labels()) {
    MeshWriterOptions options = job.mesh;
    options.sync = options.sync || job.sync;
    for (std::string& comment : options.comments) comment += ", label " + std::to_string(label);
    if (options.comments.empty()) options.comments.push_back("label " + std::to_string(label));
    const std::string file = label_file_name(job.output_pattern, label);
    std::unique_ptr<MeshWriter> writer = open_mesh_writer(file, job.format, options);
    LabelSurface surface;
    const Status status =
        job.pieces.active()
            ? write_kept_pieces(spool, label, pixels, job.pieces, directory, *writer,
                                &surface.pieces)
            : spool.replay(label, *writer);
    if (status == Status::sink_refused && writer->error()) throw *writer->error();
    if (status != Status::ok)
      throw Error(file, std::string("writing failed: ") + status_message(status));
    if (job.pieces.active() && surface.pieces.polygons_kept == 0) {
      report.dropped.push_back(label);  // nothing left: no file (the temporary goes with it)
      continue;
    }
    writer->complete();  // sealed: its buffers are freed until it is published
    writers.push_back(std::move(writer));
    surface.label = label;
    surface.file = file;
    surface.vertices = job.pieces.active() ? surface.pieces.vertices_kept : counts.vertices;
    surface.polygons = job.pieces.active() ? surface.pieces.polygons_kept : counts.polygons;
    surface.faces_written = writers.back()->faces_written();
    surface.sessions = counts.sessions;
    report.surfaces.push_back(surface);
  }
  // Nothing to write is a failure, not an empty success: the user asked for meshes.
  if (report.surfaces.empty())
    throw Error(job.input_label,
                !report.dropped.empty()
                    ? "--min-faces dropped every piece of every label: nothing to write"
                : job.labels.all
                    ? "no label in the volume: every voxel is 0, negative or not a whole number"
                    : "none of the labels asked for is in the volume");
  report.write_s = seconds_since(write_start);
  report.total_s = seconds_since(start);
  report.peak_memory_bytes = peak_resident_bytes();

  std::optional<OutputFile> stats_file;
  if (!job.stats_path.empty()) {
    stats_file.emplace(job.stats_path, job.sync);
    const std::string json = label_report_json(report);
    stats_file->write(json.data(), json.size());
    stats_file->seal();
  }
  std::vector<OutputFile*> sealed;
  for (const auto& writer : writers) sealed.push_back(writer->output_file());
  if (stats_file) sealed.push_back(&*stats_file);
  publish_together(sealed);

  if (!job.quiet) {
    std::uint64_t polygons = 0;
    for (const LabelSurface& surface : report.surfaces) polygons += surface.polygons;
    std::fprintf(stderr,
                 "%zu labels, %s polygons in %zu files; at most %u engines at once (%s bytes "
                 "each), spool %s bytes\n"
                 "  read %.3f s, extract %.3f s, write %.3f s; peak memory %.1f MiB\n",
                 report.surfaces.size(), grouped(polygons).c_str(), report.surfaces.size(),
                 report.most_engines, grouped(report.engine_bytes).c_str(),
                 grouped(report.spool_bytes).c_str(), report.read_s, report.extract_s,
                 report.write_s, static_cast<double>(report.peak_memory_bytes) / (1 << 20));
  }
  return report;
}

std::string label_report_json(const LabelReport& r) {
  std::string json = "{\n  \"input\": " + json_string(r.input) + ",\n";
  char line[256];
  std::snprintf(line, sizeof line, "  \"volume\": {\"width\": %u, \"height\": %u, \"depth\": %u},\n",
                r.volume.width, r.volume.height, r.volume.depth);
  json += line;
  json += "  \"labels\": [";
  for (std::size_t i = 0; i < r.surfaces.size(); ++i) {
    const LabelSurface& s = r.surfaces[i];
    json += i == 0 ? "\n" : ",\n";
    std::snprintf(line, sizeof line,
                  "    {\"label\": %u, \"vertices\": %llu, \"polygons\": %llu, \"faces_written\": "
                  "%llu, \"engines\": %llu, ",
                  s.label, static_cast<unsigned long long>(s.vertices),
                  static_cast<unsigned long long>(s.polygons),
                  static_cast<unsigned long long>(s.faces_written),
                  static_cast<unsigned long long>(s.sessions));
    json += line;
    if (r.pieces) {
      std::snprintf(line, sizeof line,
                    "\"pieces\": %llu, \"pieces_kept\": %llu, \"piece_starts\": %llu, ",
                    static_cast<unsigned long long>(s.pieces.pieces),
                    static_cast<unsigned long long>(s.pieces.pieces_kept),
                    static_cast<unsigned long long>(s.pieces.piece_starts));
      json += line;
    }
    json += "\"file\": " + json_string(s.file) + "}";
  }
  json += r.surfaces.empty() ? "],\n" : "\n  ],\n";
  json += "  \"labels_dropped\": [";
  for (std::size_t i = 0; i < r.dropped.size(); ++i)
    json += (i == 0 ? "" : ", ") + std::to_string(r.dropped[i]);
  json += "],\n";
  std::snprintf(line, sizeof line,
                "  \"memory\": {\"most_engines_at_once\": %u, \"bytes_per_engine\": %llu, "
                "\"spool_index_bytes\": %llu, \"start_bytes\": %llu, \"peak_bytes\": %llu},\n",
                r.most_engines, static_cast<unsigned long long>(r.engine_bytes),
                static_cast<unsigned long long>(r.spool_index_bytes),
                static_cast<unsigned long long>(r.start_memory_bytes),
                static_cast<unsigned long long>(r.peak_memory_bytes));
  json += line;
  std::snprintf(line, sizeof line, "  \"spool_bytes\": %llu,\n",
                static_cast<unsigned long long>(r.spool_bytes));
  json += line;
  std::snprintf(line, sizeof line,
                "  \"seconds\": {\"read\": %.6f, \"extract\": %.6f, \"write\": %.6f, \"total\": "
                "%.6f}\n}\n",
                r.read_s, r.extract_s, r.write_s, r.total_s);
  json += line;
  return json;
}

}  // namespace mvox
