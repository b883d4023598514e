#pragma once
// Slab-parallel extraction: the volume is cut into slabs of consecutive slices, worker threads
// each run an engine over one slab at a time (Engine::begin_slab), and the slabs' output goes
// into the mesh writer in slab order, so that the mesh is the one a single engine writes, byte
// for byte, for any number of workers.
//
// Threads: `threads` workers extract and write; the caller reports progress. Where the input
// allows (own_range_reader: files), each worker reads its own slab's slices, so decoding runs
// in parallel too; otherwise one more thread reads the source once, in order, and hands each
// slice to the workers whose slabs need it (a slab also needs the slice before it, and with
// normals one more on each side). The worker of the lowest slab not yet written writes its
// engine's output straight into the writer; the others record theirs in chunks of about half a
// MiB, vertices already placed with the writer's VertexPlacement (slab_recorder.h), until the
// turn comes to their slab (slab_write_turns.h).
//
// Memory is fixed, whatever the depth: per worker an engine workspace, a slice window when
// normals are wanted, its own slab reader or a slab's slice buffers (slab_buffer_slices), and
// kChunksPerWorker chunks, up to most_chunks_per_worker() when a worker ahead would otherwise
// wait for its turn; past that it waits. slab_pipeline_bytes() says how much.
//
// A reading error is reported as one thread reading in order would report it: the first bad
// slice in the volume, even when workers reading in parallel came to a later one first.
#include <array>
#include <cstdint>
#include <string>

#include "mvox/engine.h"
#include "mvox/slice_source.h"
#include "pipeline/pipeline.h"

namespace mvox {

class MeshWriter;
class SurfacePicture;

struct SlabOptions {
  unsigned threads = 2;           // extracting workers, >= 1
  std::uint32_t slab_slices = 0;  // slices per slab; 0: default_slab_slices()
  // Gradient normals, computed in each slab (the writer must have normals_given) with the voxel
  // size the mesh is written with.
  bool normals = false;
  std::array<double, 3> spacing = {1, 1, 1};
  // A picture (borrowed; may be null), drawn in parallel: each worker draws its slabs into a
  // layer of its own (SurfacePicture::new_layer), and the layers are composited into it at
  // the end, giving the picture one engine draws. With frames or a live window
  // (SurfacePicture::follows_slices), each worker also composites its layer into the picture
  // whenever it has drawn a slab, so that they show it growing (slab_picture_follower.h).
  SurfacePicture* picture = nullptr;
  bool smooth_picture = false;  // the picture is shaded with gradient normals
  // Each worker keeps a slice window: for the mesh's normals, or the picture's smooth shading.
  bool needs_window() const { return normals || smooth_picture; }
  // Chunks of recorded output a worker may hold at most (SlabWriteTurns): 0 for
  // most_chunks_per_worker(). A plan that must fit a memory budget can ask for fewer.
  unsigned most_chunks = 0;
  // For slab_pipeline_bytes(): the working bytes of each worker's own slab reader, when the
  // input is read that way (own_range_reader); 0 when one thread reads and fans slices out.
  std::uint64_t reader_bytes = 0;
  // For slab_pipeline_bytes(): formatted_bytes_per_polygon() of the mesh's format, when the
  // mesh writer has a face formatter (MeshWriter::face_formatter: STL) whose records the
  // workers then keep; else 0. run_slab_pipeline() asks the writer itself.
  std::size_t formatted_bytes_per_polygon = 0;
  // For slab_pipeline_bytes(): formatted_bytes_per_vertex() of the mesh's format, when the mesh
  // writer has a VertexTextFormatter (MeshWriter::vertex_text_formatter: OBJ, ASCII PLY), whose
  // lines the workers then keep; else 0. run_slab_pipeline() asks the writer itself.
  std::size_t formatted_bytes_per_vertex = 0;
};

class RangeReadable;
// The source as a RangeReadable when each worker can read its own slab's slices from it (files),
// or null when one thread must read it in order and hand the slices out (a pipe).
const RangeReadable* own_range_reader(const SliceSource& source);

// Chunks of recorded output a worker starts with. A slab of the default size (about 1 MiB of
// samples) emits about 1.2 MB on the paper's engine: with three chunks a worker ahead often had
// to wait for the turn before it could start its next slab; with four it seldom does.
constexpr unsigned kChunksPerWorker = 4;

// The fewest chunks a worker may grow to (fewer, never below kChunksPerWorker, only when a
// memory budget leaves less room: mesh_job.cpp). Writing a file is slower than extracting: the
// worker whose turn it is writes its slab into the file as it extracts it, and the worker ahead
// needs room for the slab it has recorded and the next one (each slab starts a chunk of its
// own), or it waits, and the two take turns for the rest of the run. Two threads, raw
// 256x256x1024 to PLY, medians of 15 rounds: 37.4 ms with four, six of the rounds at 43-51 ms;
// 36.0 ms with six, every round but one at 36-38 ms. Their peak memory went from 13.5 to 15.9-16.0
// MiB at 4,096 slices, as much as two one-thread runs (7.8-8.0 MiB each); eight gained no more
// speed for 16.2 MiB (docs/scaling.md). In memory, where writing costs little, a worker seldom
// takes a fifth.
constexpr unsigned kFewestMostChunks = 6;

// The chunks a worker may grow to, for slabs of `slab_slices` slices of `volume`: room for
// about one byte of recorded output per voxel of its slab (a chunk holds 512 KiB and reserves
// up to about 1.5 MiB, SlabChunk::reserved_bytes), at least kFewestMostChunks and at most
// kMostChunks. Large slices make slabs of 8 slices (default_slab_slices) whose output does not
// fit four chunks: at 1024x1024 a slab emits about 5 MB, and a worker ahead that waits for free
// chunks takes turns with the other instead of working beside it. A worker takes a chunk more
// only when all its chunks hold output not yet written: it is then ahead of the writer by what
// they hold (a slab at least, as each slab starts a chunk of its own).
unsigned most_chunks_per_worker(const VolumeInfo& volume, std::uint32_t slab_slices);
// 64 chunks: the 2048x2048 slabs of 8 slices. Beyond, recording (written to memory and read
// back) limits two workers more than waiting does, and each chunk costs memory.
constexpr unsigned kMostChunks = 64;

// Slices per slab for slices of this size: about 1 MiB of samples a slab, 8 to 128 slices.
// A slab's fixed cost (the slice before it is classified again: 1/8 more classification at 8
// slices) wants thick slabs. Thin ones win: each worker holds a whole slab's slices
// (slab_buffer_slices), and the writer takes slabs in order, so a worker that runs ahead must
// keep its slab's output in its chunks until the writer comes to it; when a slab's output does
// not fit, the worker waits, and the workers take turns instead of working together.
std::uint32_t default_slab_slices(const VolumeInfo& volume);
// The slices per slab a run takes: `requested` (at least 4) or, for 0, the default.
std::uint32_t slab_slices_of(const VolumeInfo& volume, std::uint32_t requested);
// The slabs the volume is cut into with slab_slices_of(volume, requested) slices each.
std::uint32_t slab_count(const VolumeInfo& volume, std::uint32_t requested);
// Slice buffers per worker: every slice its slab needs. Slices are read once, in order, so the
// reader can hand the next slab to the next worker only once this one has its whole slab;
// with fewer, the workers would take turns.
std::uint32_t slab_buffer_slices(std::uint32_t slab_slices, bool normals);

// The memory the slab pipeline adds for `threads` workers: their workspaces, windows, slice
// buffers and chunks (SlabChunk::reserved_bytes each, as many as a worker may hold); picture
// layers not included (PictureLayer::bytes each). slab_chunk_bytes(): what one chunk more on
// every worker adds.
std::uint64_t slab_pipeline_bytes(const VolumeInfo& volume, const EngineOptions& engine,
                                  const SlabOptions& options);
std::uint64_t slab_chunk_bytes(const EngineOptions& engine, const SlabOptions& options);

// Extracts every slice of `source` into `mesh` (may be null when options.picture is set) and
// options.picture as run_pipeline() does with one engine, with the same result (extraction
// counters summed over the slabs; the picture's counters are the layers', summed), with at
// most one worker per slab. Phase times overlap here: read_s is the time inside the sources
// (the reading thread's, or the workers' summed), write_s the workers' time inside the writer,
// summed, render_s compositing the picture's layers, extract_s the rest of the wall time (0
// when the summed writing exceeds it). Throws
// mvox::Error naming `input_label` for an engine error, a source that ends before its depth, or
// whatever the source throws; the writer's own error is left in the writer (status
// sink_refused), as run_pipeline() leaves it.
PipelineResult run_slab_pipeline(SliceSource& source, double threshold, const EngineOptions& engine,
                                 MeshWriter* mesh, const SlabOptions& options,
                                 const std::string& input_label,
                                 const ProgressCallback& progress = {});

}  // namespace mvox
