// What rendering adds to extraction on the paper's three datasets, against the goal that drawing
// the picture costs at most half of what extracting the surface does. Every slice is decoded
// into memory first; then, interleaved, N runs of each of
//   (a) extraction alone: the fast engine (merge rules) into a sink that only counts;
//   (b) extraction and rendering: the same engine sending polygons by value, fed one slice
//       behind a SliceWindow (stream_volume), into a RenderSink with gradient normals drawing a
//       512x512 z-buffer picture from the default orthographic view fitted to the volume.
// Rendering time is (b) - (a): polygons by value, the window's copies, normals and drawing.
// The time spent inside the RenderSink (normals and drawing) is measured too, by a sink that
// wraps it and reads the clock around each batch. Medians of the N runs are reported.
//
//   mvox_bench_render [--datasets DIR] [--runs N] [--dataset NAME] [--save-images DIR]
//
// Prints the command line, a Markdown table per dataset and a summary on standard output; with
// --save-images, writes DIR/NAME.png, the picture of the last run (b), to check it by eye.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_arguments.h"
#include "mvox/camera.h"
#include "mvox/counting_sink.h"
#include "mvox/engine.h"
#include "mvox/fan_out_sink.h"
#include "mvox/render_sink.h"
#include "mvox/slice_window.h"
#include "mvox/stream_volume.h"
#include "mvox/vertex_normals.h"
#include "mvox/workspace_buffer.h"
#include "mvox/zbuffer_renderer.h"
#include "paper_datasets.h"
#include "pipeline/mesh_job.h"
#include "write/slice_image_writer.h"

namespace mvox::bench {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::uint32_t kImageSide = 512;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The time spent in a FanOutSink's sinks, all together, told by its observer before and after
// each call. The engine sends a few batches per slice, so the clock reads cost nothing
// measurable.
struct SinkSeconds {
  static void observe(void* context, SinkCall, int sink) {
    auto& self = *static_cast<SinkSeconds*>(context);
    if (sink < 0)
      self.start = Clock::now();
    else
      self.seconds += seconds_since(self.start);
  }
  Clock::time_point start;
  double seconds = 0;
};

// Memory for both kinds of run, allocated and touched once per dataset so that no run pays for
// first-touch page faults.
struct Buffers {
  Buffers(const VolumeInfo& info, const EngineOptions& counting, const EngineOptions& rendering)
      : counting_engine(engine_workspace_bytes(info.width, info.height, counting)),
        rendering_engine(engine_workspace_bytes(info.width, info.height, rendering)),
        window(slice_window_bytes(info.width, info.height, info.type)),
        zbuffer(zbuffer_workspace_bytes(kImageSide, kImageSide) / sizeof(float) + 1) {
    std::memset(counting_engine.data(), 0, counting_engine.bytes());
    std::memset(rendering_engine.data(), 0, rendering_engine.bytes());
  }
  WorkspaceBuffer counting_engine;
  WorkspaceBuffer rendering_engine;
  std::vector<unsigned char> window;
  std::vector<float> zbuffer;
};

struct Runs {
  std::vector<double> extraction, rendering, inside_sink;  // seconds, one per run
  EngineCounters extraction_counters, rendering_counters;
  RenderCounters render_counters;
};

// (a): seconds from engine.init() to finish(), or -1 on an engine error.
double extract(const LoadedVolume& volume, double threshold, const EngineOptions& options,
               WorkspaceBuffer& workspace, EngineCounters* counters) {
  const VolumeInfo& info = volume.info;
  LoadedVolumeSource source(volume);
  CountingSink sink;
  Engine engine;
  const auto start = Clock::now();
  if (engine.init(workspace.data(), workspace.bytes(), info.width, info.height, threshold, options,
                  &sink) != Status::ok ||
      stream_volume(source, engine) != Status::ok)
    return -1;
  const double seconds = seconds_since(start);
  *counters = engine.counters();
  return seconds;
}

// (b): seconds from the window's and renderer's init() to the engine's finish(), or -1 on an
// error; `inside_sink` gets the part spent in the RenderSink.
double extract_and_render(const LoadedVolume& volume, double threshold,
                          const EngineOptions& options, const Camera& camera, Buffers& buffers,
                          ZBufferRenderer& renderer, EngineCounters* counters,
                          double* inside_sink) {
  const VolumeInfo& info = volume.info;
  const glm::vec3 spacing(info.spacing[0], info.spacing[1], info.spacing[2]);
  const glm::vec3 origin(info.origin[0], info.origin[1], info.origin[2]);
  LoadedVolumeSource source(volume);
  SliceWindow window;
  Engine engine;
  const auto start = Clock::now();
  if (window.init(buffers.window.data(), buffers.window.size(), info.width, info.height,
                  info.type) != Status::ok ||
      renderer.init(buffers.zbuffer.data(), buffers.zbuffer.size() * sizeof(float), camera) !=
          Status::ok)
    return -1;
  const VertexNormals normals(window, spacing);
  RenderSink render(renderer, spacing, origin, &normals);
  FanOutSink timed;
  timed.add(&render);
  SinkSeconds in_render;
  timed.set_observer(SinkSeconds::observe, &in_render);
  if (engine.init(buffers.rendering_engine.data(), buffers.rendering_engine.bytes(), info.width,
                  info.height, threshold, options, &timed) != Status::ok ||
      stream_volume(source, engine, {}, &window) != Status::ok)
    return -1;
  const double seconds = seconds_since(start);
  *counters = engine.counters();
  *inside_sink = in_render.seconds;
  return seconds;
}

std::string command_line(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i) line += ' ';
    line += arg.find_first_of(" \t'\"*?") == std::string::npos ? arg : "'" + arg + "'";
  }
  return line;
}

std::string milliseconds(const std::vector<double>& seconds) {
  const auto [low, high] = std::minmax_element(seconds.begin(), seconds.end());
  char text[96];
  std::snprintf(text, sizeof text, "%.1f ms (runs %.1f .. %.1f)", median(seconds) * 1e3, *low * 1e3,
                *high * 1e3);
  return text;
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f%%", fraction * 100);
  return text;
}

void print_table(const PaperDataset& dataset, const LoadedVolume& volume, const Runs& runs,
                 const std::string& image_path) {
  const VolumeInfo& info = volume.info;
  const double a = median(runs.extraction), b = median(runs.rendering);
  const RenderCounters& r = runs.render_counters;
  std::printf("### %s\n\n| figure | value |\n|---|---|\n", dataset.name.c_str());
  std::printf("| voxels | %ux%ux%u %s, spacing %g,%g,%g (%.1f Mvoxel) |\n", info.width, info.height,
              info.depth, sample_type_name(info.type), info.spacing[0], info.spacing[1],
              info.spacing[2], double(info.width) * info.height * info.depth / 1e6);
  std::printf("| threshold | %g |\n", dataset.threshold);
  const EngineCounters& e = runs.extraction_counters;
  std::uint64_t corners = 0;
  for (int size = 0; size <= kMaxPolygonVertices; ++size)
    corners += size * e.polygons_by_size[size];
  std::printf("| polygons | %s |\n", grouped(e.polygons).c_str());
  std::printf("| vertices / polygon corners (normals and transforms are per corner) | %s / %s |\n",
              grouped(e.vertices).c_str(), grouped(corners).c_str());
  std::printf("| (a) extraction | %s |\n", milliseconds(runs.extraction).c_str());
  std::printf("| (b) extraction + rendering | %s |\n", milliseconds(runs.rendering).c_str());
  std::printf("| rendering = (b) - (a) | %.1f ms |\n", (b - a) * 1e3);
  std::printf("| rendering inside the RenderSink (normals, drawing) | %s |\n",
              milliseconds(runs.inside_sink).c_str());
  std::printf("| render share of extraction, ((b) - (a)) / (a) | %s |\n",
              percent((b - a) / a).c_str());
  std::printf("| render share of total, ((b) - (a)) / (b) | %s |\n", percent((b - a) / b).c_str());
  std::printf("| goal: rendering at most half the extraction time | %s |\n",
              (b - a) <= 0.5 * a ? "met" : "**not met**");
  std::printf("| polygons drawn / clipped | %s / %s |\n", grouped(r.polygons).c_str(),
              grouped(r.polygons_clipped).c_str());
  std::printf("| triangles drawn / culled | %s / %s |\n", grouped(r.triangles_drawn).c_str(),
              grouped(r.triangles_culled).c_str());
  std::printf("| fragments covered / written (of %s pixels) | %s / %s |\n",
              grouped(std::uint64_t{kImageSide} * kImageSide).c_str(),
              grouped(r.fragments_covered).c_str(), grouped(r.fragments_written).c_str());
  if (!image_path.empty()) std::printf("| picture | `%s` |\n", image_path.c_str());
  std::printf("\n");
  std::fflush(stdout);
}

struct Summary {
  std::string dataset;
  double extraction = 0, rendering = 0, inside_sink = 0;  // median seconds
};

void print_summary(const std::vector<Summary>& rows) {
  std::printf(
      "### Summary\n\n| dataset | (a) extraction | (b) + rendering | rendering | in the sink | "
      "share of extraction | share of total | at most half? |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const Summary& row : rows) {
    const double a = row.extraction, b = row.rendering;
    std::printf("| %s | %.1f ms | %.1f ms | %.1f ms | %.1f ms | %s | %s | %s |\n",
                row.dataset.c_str(), a * 1e3, b * 1e3, (b - a) * 1e3, row.inside_sink * 1e3,
                percent((b - a) / a).c_str(), percent((b - a) / b).c_str(),
                (b - a) <= 0.5 * a ? "yes" : "no");
  }
}

// `mvox extract` as run from the command line, in process: read the files, extract, write the
// PLY, and with `picture` also render and write a 512x512 PNG (default view). Outputs go to
// `folder` and are overwritten each run.
RunReport end_to_end(const PaperDataset& dataset, bool picture, const std::string& folder) {
  const auto open_start = Clock::now();
  auto source = open_dataset(dataset);
  MeshJob job;
  job.source_open_s = seconds_since(open_start);
  job.input_label = dataset.name;
  job.threshold = dataset.threshold;
  job.output = folder + "/" + dataset.name + ".ply";
  for (int axis = 0; axis < 3; ++axis) job.mesh.transform.spacing[axis] = dataset.spacing[axis];
  job.quiet = true;
  if (picture) job.picture.image_path = folder + "/" + dataset.name + ".png";
  return run_mesh_job(*source, job);
}

struct EndToEnd {
  std::string name;
  std::vector<double> read, extract, write, render, total, total_without_picture;
};

void print_end_to_end(const std::vector<EndToEnd>& rows) {
  std::printf(
      "### End to end: `mvox extract ... -o mesh.ply --image picture.png`\n\n"
      "| dataset | read | extract | write PLY | render + PNG | total | render share of total | "
      "render / extract | total without --image |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (const EndToEnd& row : rows) {
    const double render = median(row.render), total = median(row.total);
    std::printf("| %s | %.1f ms | %.1f ms | %.1f ms | %.1f ms | %.1f ms | %s | %s | %.1f ms |\n",
                row.name.c_str(), median(row.read) * 1e3, median(row.extract) * 1e3,
                median(row.write) * 1e3, render * 1e3, total * 1e3, percent(render / total).c_str(),
                percent(render / median(row.extract)).c_str(),
                median(row.total_without_picture) * 1e3);
  }
  std::printf("\n");
}

}  // namespace
}  // namespace mvox::bench

int main(int argc, char** argv) {
  using namespace mvox;
  using namespace mvox::bench;
  BenchArguments arguments;
  if (!parse_bench_arguments(argc, argv, MVOX_SHARED_DATASETS, {"--dataset", "--save-images"},
                             &arguments))
    return 2;
  const std::string root = arguments.datasets, only = arguments.value("--dataset");
  const std::string image_folder = arguments.value("--save-images");
  const int runs = arguments.runs;
  try {
    std::vector<PaperDataset> datasets = paper_datasets(root);
    if (!only.empty())
      datasets.erase(std::remove_if(datasets.begin(), datasets.end(),
                                    [&](const PaperDataset& d) { return d.name != only; }),
                     datasets.end());
    if (datasets.empty()) {
      std::fprintf(stderr, "mvox_bench_render: no dataset %s found under %s\n", only.c_str(),
                   root.c_str());
      return 1;
    }
    if (!image_folder.empty()) std::filesystem::create_directories(image_folder);

    std::printf("`%s`\n\n", command_line(argc, argv).c_str());
    const EngineOptions counting;  // fast engine, merge rules
    EngineOptions rendering = counting;
    rendering.polygon_geometry = true;
    std::vector<Summary> summary;
    for (const PaperDataset& dataset : datasets) {
      const LoadedVolume volume = load_dataset(dataset);
      glm::vec3 box_min, box_max;
      volume_bounds(volume.info, &box_min, &box_max);
      const Camera camera = fit_camera(box_min, box_max, ViewOptions{}, kImageSide, kImageSide);
      Buffers buffers(volume.info, counting, rendering);
      ZBufferRenderer renderer;
      Runs measured;
      for (int run = 0; run < runs; ++run) {  // interleaved, so drift hits (a) and (b) alike
        double inside_sink = 0;
        const double a = extract(volume, dataset.threshold, counting, buffers.counting_engine,
                                 &measured.extraction_counters);
        const double b = extract_and_render(volume, dataset.threshold, rendering, camera, buffers,
                                            renderer, &measured.rendering_counters, &inside_sink);
        if (a < 0 || b < 0) {
          std::fprintf(stderr, "mvox_bench_render: %s: engine or renderer error\n",
                       dataset.name.c_str());
          return 1;
        }
        measured.extraction.push_back(a);
        measured.rendering.push_back(b);
        measured.inside_sink.push_back(inside_sink);
      }
      measured.render_counters = renderer.counters();
      if (measured.extraction_counters.polygons != measured.rendering_counters.polygons ||
          measured.render_counters.polygons != measured.rendering_counters.polygons) {
        std::fprintf(stderr, "mvox_bench_render: %s: polygon counts differ between (a) and (b)\n",
                     dataset.name.c_str());
        return 1;
      }
      std::string image_path;
      if (!image_folder.empty()) {
        image_path = image_folder + "/" + dataset.name + ".png";
        write_slice_image(image_path, renderer.picture());
      }
      print_table(dataset, volume, measured, image_path);
      summary.push_back({dataset.name, median(measured.extraction), median(measured.rendering),
                         median(measured.inside_sink)});
    }
    print_summary(summary);

    // End to end, the same datasets, interleaved with and without the picture.
    const std::string folder =
        (std::filesystem::temp_directory_path() / "mvox_bench_render").string();
    std::filesystem::create_directories(folder);
    std::vector<EndToEnd> rows;
    for (const PaperDataset& dataset : datasets) {
      EndToEnd row;
      row.name = dataset.name;
      for (int run = 0; run < runs; ++run) {
        const RunReport with = end_to_end(dataset, true, folder);
        const RunReport without = end_to_end(dataset, false, folder);
        const PhaseTimes& t = with.result.times;
        row.read.push_back(t.read_s);
        row.extract.push_back(t.extract_s);
        row.write.push_back(t.write_s);
        row.render.push_back(t.render_s);
        row.total.push_back(t.total_s);
        row.total_without_picture.push_back(without.result.times.total_s);
      }
      rows.push_back(row);
    }
    std::filesystem::remove_all(folder);
    print_end_to_end(rows);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mvox_bench_render: %s\n", e.what());
    return 1;
  }
  return 0;
}
