#pragma once
// The job of `mvox-mpi extract`: one mesh file written by many processes, the same bytes as
// `mvox extract` writes alone.
//
// Rank r of R takes slices [depth * r / R, depth * (r + 1) / R) as one slab (Engine::begin_slab)
// and reads them itself, so the input must be files every rank can read from anywhere (image
// stacks, raw slices or volume, NRRD and MetaImage with raw data: read/range_readable.h).
// Three collective steps:
//   1. count: each rank runs its slab's engine and keeps only how the slab ended (its vertex
//      counts and polygons by size, SlabSummary); all ranks exchange these, and each knows from
//      the ranks before it where its vertex numbers start (SlabJoin). For binary PLY and STL,
//      whose records have sizes that follow from those counts, each rank also knows now where
//      its records go in the file, and the ranks open it together (MPI-IO).
//   2. write a part: each rank runs its engine again into a writer of the mesh's format that
//      writes a part (MeshWriterOptions::part): no head, vertices numbered from there on. Binary
//      PLY and STL parts go straight into the file at their offsets (placed_part_writer.h): PLY
//      its vertex records among the vertices, its face records among the faces. Parts of other
//      formats (ASCII PLY, OBJ) wait in a temporary file beside the output.
//   3. write together: rank 0 writes the head with the whole mesh's counts. Parts that waited
//      are copied in: the ranks exchange their sizes, an exclusive scan gives each its offsets,
//      and each writes its part with MPI-IO at those offsets (shared_mesh_file.h).
// A picture is drawn in step 2, each rank its slab into a layer of its own, and composited in
// step 3 by one reduction over the ranks (picture_reduction.h); without a mesh, step 2 is the
// only extraction.
// Rank 0 then makes the file appear, as one process would: a temporary renamed onto the target
// only when every rank has succeeded (output_file.h), with the --stats report beside it.
//
// Memory per rank is one engine's (workspace, reader, window, one recorded chunk, the writer's
// buffers, the picture's z-buffers), whatever the depth and the number of ranks. The extraction
// runs twice, which costs less than waiting: without the counts no rank could number its vertices
// before the ranks before it were done, nor, for PLY, know where the faces start. Counting first
// also spares binary PLY the second copy of its faces that one process writing alone makes.
#include "mpi/mpi_world.h"
#include "mvox/slice_source.h"
#include "pipeline/mesh_job.h"

namespace mvox {

// Runs `job` on this rank; every rank of `world` calls it with the same job. Throws mvox::Error
// on the rank that reports a failure and OtherRankFailed on the others (MpiWorld::step).
// Refuses, as usage errors, what a distributed run cannot do: frames and the live window (one
// process writes or shows the picture as it grows), standard output, --threads, and an input
// that the ranks cannot each read.
void run_distributed_mesh_job(SliceSource& source, const MeshJob& job, MpiWorld& world);

}  // namespace mvox
