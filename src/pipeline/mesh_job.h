#pragma once
// The job behind `mvox extract` and `mvox demo`: stream a slice source through the engine into a
// mesh file (PLY, STL or OBJ), with progress, a summary line and an optional --stats report.
#include <optional>
#include <string>
#include <vector>

#include "labels/piece_filter.h"
#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "picture/surface_picture.h"
#include "pipeline/memory_plan.h"
#include "write/mesh/mesh_format.h"
#include "write/stats_json.h"

namespace mvox {

struct MeshJob {
  std::string input_label;  // for messages and the report: the input as the user named it
  double threshold = 0;     // in sample units
  EngineOptions engine;
  std::string output;  // mesh path, "-" for standard output; empty: no mesh (a picture only)
  MeshFormat format = MeshFormat::ply;
  // Placement, comments, --triangulate; its `normals` is set by the job when `normals` is true.
  MeshWriterOptions mesh;
  bool normals = false;  // write gradient normals (PLY nx, ny, nz; OBJ vn) into the mesh
  // --smooth N: iterations of edge-held smoothing (postprocess/edge_smoothing.h), 0 for none.
  // One engine does it (not slabs): the smoothing needs the layers on both sides of a slab's
  // boundary.
  std::uint32_t smooth_iterations = 0;
  // --decimate / --max-error (postprocess/layer_decimation.h); one engine does it, with flat
  // pictures and no --normals (vertices may leave long after the slices around them).
  std::optional<DecimationOptions> decimation;
  // --largest, --min-faces: the mesh is spooled (labels/label_spool.h) and only the pieces kept
  // are written, after extraction; one engine, no picture, no --normals.
  PieceRule pieces;
  PictureOptions picture;
  std::string stats_path;  // empty: no report
  // Make every output durable (fsync) before it appears: --sync. Sets the mesh's and the
  // picture's own `sync` too.
  bool sync = false;
  bool quiet = false;  // no progress line, no summary
  // Extracting threads (--threads): above 1, the volume is extracted in slabs, in parallel
  // (slab_extraction.h), mesh and picture the same bytes as one thread (frames and the live
  // window follow the slabs as they are drawn: slab_picture_follower.h). 1: one engine.
  // 0: one per core for volumes of kAutoSlabVolumeBytes or more, one engine below.
  unsigned threads = 1;
  // With one engine, a reading thread fills the next slices while the engine works
  // (prefetching_source.h), when it pays (one_engine_helpers). Off, the whole run takes one
  // thread: --threads 1, for single-core devices.
  bool read_ahead = true;
  std::uint32_t slab_slices = 0;  // slices per slab (--slab-slices); 0: default_slab_slices()
  double source_open_s = 0;       // time the caller spent opening the source (counted as reading)
  // Every file the source reads: no output may replace one (output_targets.h).
  std::vector<std::string> input_files;
  // The most memory the run may take (memory_plan.h): checked against the plan before
  // anything is allocated or read. Zero bytes: no limit.
  MemoryBudget budget;
  // Plan and check only: print the plan on standard output, allocate, read and write nothing.
  bool dry_run = false;
};

// Runs the job; throws mvox::Error naming the file or stage at fault. Before anything is
// allocated or created, the outputs are checked against the inputs and each other
// (output_targets.h) and the run's memory plan against job.budget. On any failure no output
// file is left behind (or a previous one is left untouched); the mesh, the picture and the
// report appear together at the end. Frames, written during the run, are the exception.
RunReport run_mesh_job(SliceSource& source, const MeshJob& job);

// The report's description of the run, before it runs: input, outputs, volume with the
// placement the mesh is made with, threshold, method; memory at the start.
RunReport start_run_report(const SliceSource& source, const MeshJob& job);
// Throws mvox::Error when the job has nothing to write, an option that needs a mesh without
// one, or an output that would land on an input or another output (output_targets.h).
// `depth`: the volume's, for the frames' names.
void check_job_outputs(const MeshJob& job, std::uint32_t depth);

// What the job will allocate for `source` (memory_plan.h): the engine's workspace, the reader's
// buffers, reading ahead, the slice window for normals, the picture and the mesh writer.
// `engine` as the job will run it (polygon_geometry set when a sink needs it).
MemoryPlan plan_job_memory(const SliceSource& source, const MeshJob& job,
                           const EngineOptions& engine);

// With threads = 0, volumes of this many bytes of samples or more are extracted in slabs by one
// worker per core. Below it, starting the workers costs about what they save: measured on this
// project's 2-core machine, two workers beat one engine with a reading thread on 64 MiB volumes
// (1.2x raw, 1.6x a PNG stack) and lose a few per cent on the paper's 8-15 MiB ones
// (docs/scaling.md).
constexpr std::uint64_t kAutoSlabVolumeBytes = std::uint64_t{64} << 20;

// Whether a run with one engine takes a reading thread (PrefetchingSource) and lets its writers
// write on a thread of their own. Never without job.read_ahead (--threads 1). When the caller
// set job.threads (--threads N above 1; MeshJob's own default of 1, as demo and library callers
// leave it), job.read_ahead alone decides. By default (job.threads 0) only when the threads
// pay: slices to decode or to wait for from a pipe (copied_slices.h), or a volume of
// kAutoSlabVolumeBytes or more. On a small volume of raw samples, handing slices and buffers
// between the threads cost more than the overlap saved: the paper's engine (8 MiB, raw) took
// 15.1 ms with them and 13.3 ms without, and 9.9 against 7.9 MiB of memory; MRbrain's 99 PNG
// slices took 34.7 ms with them and 41.6 ms without (hyperfine, 30 runs each, 2026-11-27).
bool one_engine_helpers(const SliceSource& source, const MeshJob& job);

// Why the job must run on one engine whatever --threads says, or null: smoothing and decimation
// need the layers on both sides of a slab's boundary; --largest and --min-faces keep one
// engine's mesh until the end. A sentence naming the option, for the note a run prints.
const char* why_one_engine(const MeshJob& job);

// The extracting threads the job will run `source` with: job.threads (for 0, as said above), at
// most one per slab, when the volume has at least two slabs and nothing needs one engine
// (why_one_engine), else 1.
unsigned slab_threads(const SliceSource& source, const MeshJob& job);

// The summary a run prints on standard error unless quiet: counts, times, memory.
void print_run_summary(const RunReport& report);
// What --dry-run prints on standard output: the input, the outputs, and the memory plan.
void print_dry_run(const RunReport& report, const MeshJob& job, const MemoryPlan& plan);

// "123,456": large counts are easier to read with separators.
std::string grouped(std::uint64_t value);

const char* surface_method_name(SurfaceMethod method);  // "voxels", "cubes"
const char* engine_kind_name(EngineKind kind);
const char* surface_rule_name(SurfaceRule rule);

}  // namespace mvox
