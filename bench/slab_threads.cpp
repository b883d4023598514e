// Slab-parallel extraction in memory: the volume is read into memory first, then extracted by
// one engine (run_pipeline, the one-thread rate) and by the slab pipeline with 1..N workers
// (run_slab_pipeline), into a mesh writer that formats nothing and keeps nothing, so that the
// figures are extraction and the pipeline's own costs (slices handed to workers, output recorded
// and replayed in order), not reading or writing a disk; and by 1..N engines on slabs that only
// count, the bound if handing the output on cost nothing. Rounds are interleaved; medians.
//   mvox_bench_threads VOLUME.raw WxHxD:TYPE THRESHOLD [MAX_THREADS] [RUNS]
// For example the paper's engine resampled to 256x256x1024 (mvox_bench_resample).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "mvox/counting_sink.h"
#include "mvox/engine.h"
#include "mvox/workspace_buffer.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_extraction.h"
#include "read/memory/memory_volume_source.h"
#include "read/raw/raw_format.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {
namespace {

// Takes the vertices and faces as a file writer does (placed in world coordinates by the base
// class) and only counts them.
class DiscardingMeshWriter final : public MeshWriter {
 public:
  DiscardingMeshWriter()
      : MeshWriter(MeshWriterOptions(), Faces::as_polygons, Positions::not_needed) {}
  const std::string& subject() const override { return subject_; }
  OutputFile* output_file() override { return nullptr; }

 private:
  void write_vertices(const WorldVertex*, std::size_t count) override { vertices_ += count; }
  void write_faces(const Polygon*, std::size_t count, std::uint32_t) override { faces_ += count; }
  void complete_file() override {}

  std::string subject_ = "nothing";
  std::uint64_t vertices_ = 0, faces_ = 0;
};

// The engines alone: `threads` threads each extract slabs t, t + threads, ... of `slab_slices`
// slices of the volume in memory into a sink that only counts (Engine::begin_slab), with no
// output handed anywhere. The bound the slab pipeline could reach if its output cost nothing;
// with one slab of the whole depth, one engine's own rate. Returns the polygons.
std::uint64_t engines_alone(const unsigned char* samples, const VolumeInfo& info, double threshold,
                            const EngineOptions& options, unsigned threads,
                            std::uint32_t slab_slices) {
  const std::uint32_t slabs = (info.depth + slab_slices - 1) / slab_slices;
  const std::size_t row = std::size_t{info.width} * sample_bytes(info.type);
  const std::size_t slice = row * info.height;
  auto view_of = [&](std::uint32_t z) {
    SliceView view;
    view.samples = samples + z * slice;
    view.width = info.width;
    view.height = info.height;
    view.row_stride_bytes = row;
    view.type = info.type;
    return view;
  };
  std::vector<std::uint64_t> polygons(threads, 0);
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      WorkspaceBuffer workspace(engine_workspace_bytes(info.width, info.height, options));
      for (std::uint32_t slab = t; slab < slabs; slab += threads) {
        const std::uint32_t first = slab * slab_slices;
        const std::uint32_t end = std::min(info.depth, first + slab_slices);
        CountingSink sink;
        Engine engine;
        Status status = engine.init(workspace.data(), workspace.bytes(), info.width, info.height,
                                    threshold, options, &sink);
        if (status == Status::ok && first > 0)
          status = engine.begin_slab(view_of(first - 1), first);
        for (std::uint32_t z = first; z < end && status == Status::ok; ++z)
          status = engine.push_slice(view_of(z));
        if (status == Status::ok)
          status = end == info.depth ? engine.finish() : engine.finish_slab();
        // A refusal shows as a polygon count that differs from one engine's.
        polygons[t] += status == Status::ok ? engine.counters().polygons : 0;
      }
    });
  for (std::thread& thread : pool) thread.join();
  std::uint64_t total = 0;
  for (std::uint64_t p : polygons) total += p;
  return total;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

int run(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s VOLUME.raw WxHxD:TYPE THRESHOLD [MAX_THREADS] [RUNS]\n",
                 argv[0]);
    return 2;
  }
  const RawFormat format = parse_raw_format(argv[2]);
  const double threshold = std::atof(argv[3]);
  const unsigned max_threads = argc > 4 ? static_cast<unsigned>(std::atoi(argv[4])) : 2;
  const int runs = argc > 5 ? std::atoi(argv[5]) : 5;
  if (runs < 1 || max_threads < 1) {
    std::fprintf(stderr, "%s: MAX_THREADS and RUNS must be at least 1\n", argv[0]);
    return 2;
  }

  VolumeInfo info;
  info.width = format.width;
  info.height = format.height;
  info.depth = format.depth;
  info.type = format.type;
  const std::size_t slice_bytes = std::size_t{info.width} * info.height * sample_bytes(info.type);
  std::vector<unsigned char> samples(slice_bytes * info.depth);
  std::ifstream input(argv[1], std::ios::binary);
  if (!input.read(reinterpret_cast<char*>(samples.data()),
                  static_cast<std::streamsize>(samples.size()))) {
    std::fprintf(stderr, "%s: cannot read %zu bytes\n", argv[1], samples.size());
    return 1;
  }
  swap_to_native(samples.data(), samples.size() / format.bytes_per_sample, format.bytes_per_sample,
                 format.byte_order);

  using Clock = std::chrono::steady_clock;
  EngineOptions engine;
  // Column 0: one engine; column t: the slab pipeline with t workers.
  std::vector<std::vector<double>> seconds(max_threads + 1);
  // Engines alone: column 0 one engine over the whole depth, column t t threads on slabs.
  std::vector<std::vector<double>> alone(max_threads + 1);
  std::uint64_t polygons = 0;
  for (int round = 0; round < runs; ++round) {
    for (unsigned threads = 0; threads <= max_threads; ++threads) {
      MemoryVolumeSource source(
          samples.data(), info, static_cast<std::ptrdiff_t>(slice_bytes),
          static_cast<std::ptrdiff_t>(std::size_t{info.width} * sample_bytes(info.type)));
      DiscardingMeshWriter writer;
      const auto start = Clock::now();
      PipelineResult result;
      if (threads == 0) {
        result = run_pipeline(source, threshold, engine, writer, "volume");
      } else {
        SlabOptions slabs;
        slabs.threads = threads;
        result = run_slab_pipeline(source, threshold, engine, &writer, slabs, "volume");
      }
      seconds[threads].push_back(std::chrono::duration<double>(Clock::now() - start).count());
      if (threads == 0) polygons = result.counters.polygons;
      {
        const auto alone_start = Clock::now();
        const std::uint64_t counted =
            engines_alone(samples.data(), info, threshold, engine, std::max(threads, 1u),
                          threads == 0 ? info.depth : slab_slices_of(info, 0));
        alone[threads].push_back(std::chrono::duration<double>(Clock::now() - alone_start).count());
        if (counted != polygons) {
          std::fprintf(stderr, "engines alone, %u threads: %llu polygons, one engine %llu\n",
                       threads, static_cast<unsigned long long>(counted),
                       static_cast<unsigned long long>(polygons));
          return 1;
        }
      }
      if (result.counters.polygons != polygons) {
        std::fprintf(stderr, "%u threads: %llu polygons, one engine %llu\n", threads,
                     static_cast<unsigned long long>(result.counters.polygons),
                     static_cast<unsigned long long>(polygons));
        return 1;
      }
    }
  }
  const double voxels = double(info.width) * info.height * info.depth;
  std::printf("%ux%ux%u, %llu polygons, %u slices a slab, medians of %d interleaved rounds\n\n",
              info.width, info.height, info.depth, static_cast<unsigned long long>(polygons),
              slab_slices_of(info, 0), runs);
  // The speed-up is taken round by round, against that round's one engine into a mesh writer,
  // then the median: this machine moves between fast and slow minutes, and a ratio of medians
  // would compare runs made in different ones.
  std::printf(
      "| extraction in memory | time | Mvoxels/s | vs one engine (median of the rounds' ratios; "
      "range) |\n|---|---|---|---|\n");
  auto row = [&](const std::string& name, const std::vector<double>& times) {
    std::vector<double> ratios;
    for (std::size_t r = 0; r < times.size(); ++r) ratios.push_back(seconds[0][r] / times[r]);
    const double t = median(times);
    std::printf("| %s | %.1f ms | %.0f | %.2fx (%.2f-%.2f) |\n", name.c_str(), t * 1e3,
                voxels / t / 1e6, median(ratios), *std::min_element(ratios.begin(), ratios.end()),
                *std::max_element(ratios.begin(), ratios.end()));
  };
  row("one engine, into a mesh writer", seconds[0]);
  for (unsigned threads = 1; threads <= max_threads; ++threads)
    row("slab pipeline, " + std::to_string(threads) + " worker" + (threads > 1 ? "s" : "") +
            ", into a mesh writer",
        seconds[threads]);
  row("one engine, counting only (the whole depth, one slab)", alone[0]);
  for (unsigned threads = 1; threads <= max_threads; ++threads)
    row(std::to_string(threads) + " engine" + (threads > 1 ? "s" : "") +
            " on slabs, counting only (no output handed on)",
        alone[threads]);
  return 0;
}

}  // namespace
}  // namespace mvox

int main(int argc, char** argv) {
  try {
    return mvox::run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 1;
  }
}
