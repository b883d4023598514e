#pragma once
// Sort-last compositing across processes (the picture of mvox-mpi): every rank draws its slab
// into a layer, and one reduction over the ranks keeps, for each pixel, the nearest fragment,
// ties going to the lowest rank, whose slab one process draws first. MPI_Reduce runs it as a
// tree, so rank 0 receives about two layers' worth of pixels whatever the number of ranks.
#include <cstdint>

#include "mpi/mpi_world.h"
#include "mvox/zbuffer_renderer.h"

namespace mvox {

class PictureLayer;
class SurfacePicture;

// Collective: every rank calls it with its layer (null for a rank without slices) and the
// picture's size; rank 0 gets the composited pixels into `picture` (others pass null), and the
// sum of every layer's counters into `counters`. Throws mvox::Error when MPI fails.
void reduce_picture(const MpiWorld& world, const PictureLayer* layer, std::uint32_t width,
                    std::uint32_t height, SurfacePicture* picture, RenderCounters* counters);

}  // namespace mvox
