// The paper's experiment: surface rendering time with marching cubes (T_c) and with marching
// voxels (T_v) on its three datasets, in the same pipeline, and the improvement 1 - T_v / T_c
// (the paper's Figure 16 claims about 30%). Runs of the two methods are interleaved and the
// median of N runs is reported for
//   pipeline:  `mvox extract INPUT --method M --image out.png` in process: read the files,
//              extract, render 512x512 grayscale (default view, gradient normals), write PNG;
//   in memory: the slices already decoded; extraction and rendering only (what the paper timed).
// Also: polygon, triangle and vertex counts, and the open edges each method leaves on the
// datasets and on random volumes (marching cubes' complemented ambiguous cases open holes).
//
//   mvox_bench_paper [--datasets DIR] [--runs N] [--chart FILE.png]
//
// Prints Markdown on standard output; with --chart, draws T_c and T_v per dataset as bars.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <unordered_set>
#include <vector>

#include "bar_chart.h"
#include "bench_arguments.h"
#include "mvox/camera.h"
#include "mvox/engine.h"
#include "mvox/render_sink.h"
#include "mvox/slice_window.h"
#include "mvox/vertex_normals.h"
#include "mvox/zbuffer_renderer.h"
#include "paper_datasets.h"
#include "pipeline/mesh_job.h"
#include "random_phantoms.h"
#include "mvox/stream_volume.h"
#include "mvox/workspace_buffer.h"

namespace mvox::bench {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::uint32_t kImageSide = 512;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

EngineOptions method_options(SurfaceMethod method) {
  EngineOptions options;
  options.method = method;
  return options;
}

const char* method_label(SurfaceMethod method) {
  return method == SurfaceMethod::cubes ? "marching cubes" : "marching voxels";
}

// The pipeline of `mvox extract --image`, in process; its own phase times.
RunReport pipeline(const PaperDataset& dataset, SurfaceMethod method, const std::string& folder) {
  const auto open_start = Clock::now();
  auto source = open_dataset(dataset);
  MeshJob job;
  job.source_open_s = seconds_since(open_start);
  job.input_label = dataset.name;
  job.threshold = dataset.threshold;
  job.engine = method_options(method);
  for (int axis = 0; axis < 3; ++axis) job.mesh.transform.spacing[axis] = dataset.spacing[axis];
  job.quiet = true;
  job.picture.image_path = folder + "/" + dataset.name + "_" + surface_method_name(method) + ".png";
  job.picture.width = job.picture.height = kImageSide;
  return run_mesh_job(*source, job);
}

// Extraction and rendering of decoded slices into a 512x512 picture; seconds, or -1 on error.
double in_memory(const LoadedVolume& volume, double threshold, SurfaceMethod method,
                 EngineCounters* counters, RenderCounters* drawn) {
  const VolumeInfo& info = volume.info;
  EngineOptions options = method_options(method);
  options.polygon_geometry = true;
  WorkspaceBuffer engine_memory(engine_workspace_bytes(info.width, info.height, options));
  std::vector<unsigned char> window_memory(slice_window_bytes(info.width, info.height, info.type));
  std::vector<float> zbuffer(zbuffer_workspace_bytes(kImageSide, kImageSide) / sizeof(float) + 1);
  glm::vec3 box_min, box_max;
  volume_bounds(info, &box_min, &box_max);
  const Camera camera = fit_camera(box_min, box_max, ViewOptions{}, kImageSide, kImageSide);
  const glm::vec3 spacing(info.spacing[0], info.spacing[1], info.spacing[2]);
  const glm::vec3 origin(info.origin[0], info.origin[1], info.origin[2]);
  LoadedVolumeSource source(volume);
  SliceWindow window;
  ZBufferRenderer renderer;
  Engine engine;
  const auto start = Clock::now();
  if (window.init(window_memory.data(), window_memory.size(), info.width, info.height, info.type) !=
          Status::ok ||
      renderer.init(zbuffer.data(), zbuffer.size() * sizeof(float), camera) != Status::ok)
    return -1;
  const VertexNormals normals(window, spacing);
  RenderSink render(renderer, spacing, origin, &normals);
  if (engine.init(engine_memory.data(), engine_memory.bytes(), info.width, info.height, threshold,
                  options, &render) != Status::ok ||
      stream_volume(source, engine, {}, &window) != Status::ok)
    return -1;
  const double seconds = seconds_since(start);
  *counters = engine.counters();
  *drawn = renderer.counters();
  return seconds;
}

// Counts directed polygon sides whose reverse never appears: the edges of holes.
class OpenEdgeCounter final : public PolygonSink {
 public:
  Status consume_vertices(const Vertex*, std::size_t) override { return Status::ok; }
  Status consume_polygons(const Polygon* polygons, std::size_t polygon_count) override {
    for (std::size_t p = 0; p < polygon_count; ++p)
      for (int i = 0; i < polygons[p].vertex_count; ++i)
        sides_.insert(
            key(polygons[p].vertices[i], polygons[p].vertices[(i + 1) % polygons[p].vertex_count]));
    return Status::ok;
  }
  std::size_t open_edges() const {
    std::size_t open = 0;
    for (std::uint64_t side : sides_) open += sides_.count(side << 32 | side >> 32) == 0;
    return open;
  }

 private:
  static std::uint64_t key(std::uint32_t from, std::uint32_t to) {
    return std::uint64_t{from} << 32 | to;
  }
  std::unordered_set<std::uint64_t> sides_;
};

std::size_t open_edges(SliceSource& source, double threshold, SurfaceMethod method) {
  const VolumeInfo& info = source.info();
  const EngineOptions options = method_options(method);
  WorkspaceBuffer memory(engine_workspace_bytes(info.width, info.height, options));
  OpenEdgeCounter counter;
  Engine engine;
  if (engine.init(memory.data(), memory.bytes(), info.width, info.height, threshold, options,
                  &counter) != Status::ok ||
      stream_volume(source, engine) != Status::ok)
    return static_cast<std::size_t>(-1);
  return counter.open_edges();
}

// Random 0/1 voxels as float slices.
class RandomVolumeSource final : public SliceSource {
 public:
  RandomVolumeSource(std::uint32_t side, double density)
      : phantom_({side, side, side}, 42, density), slice_(std::size_t{side} * side) {
    info_.width = info_.height = info_.depth = side;
    info_.type = SampleType::f32;
  }
  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override {
    if (z_ >= info_.depth) return false;
    for (std::uint32_t y = 0; y < info_.height; ++y)
      for (std::uint32_t x = 0; x < info_.width; ++x)
        slice_[std::size_t{y} * info_.width + x] = phantom_.density(x, y, z_);
    ++z_;
    *slice = {slice_.data(), info_.width, info_.height, info_.width * sizeof(float),
              SampleType::f32};
    return true;
  }

 private:
  sim::RandomVoxels phantom_;
  VolumeInfo info_;
  std::vector<float> slice_;
  std::uint32_t z_ = 0;
};

struct Row {
  std::string name;
  std::vector<double> pipeline[2], memory[2];  // [voxels, cubes] seconds per run
  std::vector<double> extract[2], render[2];   // the pipeline's own phases
  EngineCounters counters[2];
  RenderCounters drawn[2];
  std::size_t open[2] = {};
};

std::string ms(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f ms", seconds * 1e3);
  return text;
}

// T_v / T_c of each run pair (the two methods ran one after the other), so that the machine's
// slow swings in load cancel; the median of these is what the tables report.
std::vector<double> paired_ratios(const std::vector<double>& voxels,
                                  const std::vector<double>& cubes) {
  std::vector<double> ratios;
  for (std::size_t i = 0; i < voxels.size() && i < cubes.size(); ++i)
    ratios.push_back(voxels[i] / cubes[i]);
  return ratios;
}

void print_rows(const std::vector<Row>& rows) {
  std::printf(
      "### T_c and T_v (the paper's Figure 16)\n\n"
      "Times are medians over runs; T_v / T_c is the median of each run pair's ratio, with its "
      "range.\n\n"
      "| dataset | T_c, marching cubes | T_v, marching voxels | T_v / T_c | improvement "
      "1 - T_v/T_c | in memory: T_c | in memory: T_v | in memory: T_v / T_c |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const Row& row : rows) {
    const std::vector<double> pipeline = paired_ratios(row.pipeline[0], row.pipeline[1]);
    const std::vector<double> memory = paired_ratios(row.memory[0], row.memory[1]);
    const auto [pipeline_low, pipeline_high] =
        std::minmax_element(pipeline.begin(), pipeline.end());
    const auto [memory_low, memory_high] = std::minmax_element(memory.begin(), memory.end());
    const double ratio = median(pipeline);
    std::printf(
        "| %s | %s | %s | %.2f (%.2f .. %.2f) | **%.0f%%** | %s | %s | %.2f (%.2f .. %.2f) |\n",
        row.name.c_str(), ms(median(row.pipeline[1])).c_str(), ms(median(row.pipeline[0])).c_str(),
        ratio, *pipeline_low, *pipeline_high, (1 - ratio) * 100, ms(median(row.memory[1])).c_str(),
        ms(median(row.memory[0])).c_str(), median(memory), *memory_low, *memory_high);
  }
  std::printf(
      "\n### Where the pipeline's time goes (medians)\n\n"
      "| dataset | method | extract | render + PNG | total |\n|---|---|---|---|---|\n");
  for (const Row& row : rows)
    for (int m : {1, 0})
      std::printf("| %s | %s | %s | %s | %s |\n", row.name.c_str(),
                  method_label(m ? SurfaceMethod::cubes : SurfaceMethod::voxels),
                  ms(median(row.extract[m])).c_str(), ms(median(row.render[m])).c_str(),
                  ms(median(row.pipeline[m])).c_str());
  std::printf(
      "\n### What each method emits\n\n"
      "| dataset | marching cubes: triangles | marching voxels: polygons | vertices (both) | "
      "triangles drawn, cubes / voxels | open edges, cubes / voxels |\n"
      "|---|---|---|---|---|---|\n");
  for (const Row& row : rows) {
    const EngineCounters& v = row.counters[0];
    std::string sizes;
    for (int size = 3; size <= kMaxPolygonVertices; ++size)
      sizes +=
          (size > 3 ? ", " : "") + std::to_string(size) + ": " + grouped(v.polygons_by_size[size]);
    std::printf("| %s | %s | %s (%s) | %s | %s / %s | %s / %s |\n", row.name.c_str(),
                grouped(row.counters[1].polygons).c_str(), grouped(v.polygons).c_str(),
                sizes.c_str(), grouped(v.vertices).c_str(),
                grouped(row.drawn[1].triangles_drawn).c_str(),
                grouped(row.drawn[0].triangles_drawn).c_str(), grouped(row.open[1]).c_str(),
                grouped(row.open[0]).c_str());
  }
  std::printf("\n");
}

void print_random_volumes() {
  std::printf(
      "### Open edges on random volumes (64x64x64, each voxel inner with the given "
      "probability)\n\n| inner probability | marching cubes | marching voxels |\n|---|---|---|\n");
  for (double density : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    RandomVolumeSource cubes_source(64, density), voxels_source(64, density);
    std::printf("| %.1f | %s | %s |\n", density,
                grouped(open_edges(cubes_source, 0.5, SurfaceMethod::cubes)).c_str(),
                grouped(open_edges(voxels_source, 0.5, SurfaceMethod::voxels)).c_str());
  }
  std::printf("\n");
}

}  // namespace
}  // namespace mvox::bench

int main(int argc, char** argv) {
  using namespace mvox;
  using namespace mvox::bench;
  BenchArguments arguments;
  if (!parse_bench_arguments(argc, argv, MVOX_SHARED_DATASETS, {"--chart"}, &arguments)) return 2;
  const std::string root = arguments.datasets, chart = arguments.value("--chart");
  const int runs = arguments.runs;
  try {
    const std::vector<PaperDataset> datasets = paper_datasets(root);
    if (datasets.empty()) {
      std::fprintf(stderr, "mvox_bench_paper: no dataset found under %s\n", root.c_str());
      return 1;
    }
    const std::string folder =
        (std::filesystem::temp_directory_path() / "mvox_bench_paper").string();
    std::filesystem::create_directories(folder);
    const SurfaceMethod methods[2] = {SurfaceMethod::voxels, SurfaceMethod::cubes};
    std::vector<Row> rows;
    for (const PaperDataset& dataset : datasets) {
      Row row;
      row.name = dataset.name;
      const LoadedVolume volume = load_dataset(dataset);
      for (int run = 0; run < runs; ++run)
        for (int k = 0; k < 2; ++k) {
          const int m = (run + k) % 2;  // alternate which method goes first
          const RunReport report = pipeline(dataset, methods[m], folder);
          row.pipeline[m].push_back(report.result.times.total_s);
          row.extract[m].push_back(report.result.times.extract_s);
          row.render[m].push_back(report.result.times.render_s);
          const double seconds =
              in_memory(volume, dataset.threshold, methods[m], &row.counters[m], &row.drawn[m]);
          if (seconds < 0) throw std::runtime_error(dataset.name + ": engine or renderer error");
          row.memory[m].push_back(seconds);
        }
      for (int m = 0; m < 2; ++m) {
        auto source = open_dataset(dataset);
        row.open[m] = open_edges(*source, dataset.threshold, methods[m]);
      }
      std::fprintf(stderr, "mvox_bench_paper: %s done\n", dataset.name.c_str());
      rows.push_back(row);
    }
    std::filesystem::remove_all(folder);
    print_rows(rows);
    print_random_volumes();
    if (!chart.empty()) {
      std::vector<BarGroup> groups;
      for (const Row& row : rows)
        groups.push_back({row.name, median(row.pipeline[1]) * 1e3, median(row.pipeline[0]) * 1e3,
                          median(paired_ratios(row.pipeline[0], row.pipeline[1]))});
      draw_bar_chart(chart, "Surface rendering time (ms), read + extract + render 512x512",
                     "T_c marching cubes", "T_v marching voxels", groups);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mvox_bench_paper: %s\n", e.what());
    return 1;
  }
  return 0;
}
