#pragma once
// Sort-last compositing across processes (the picture of mvox-mpi): every rank draws its slab
// into a layer, and one reduction over the ranks keeps, for each pixel, the nearest fragment,
// ties going to the lowest rank, whose slab one process draws first. MPI_Reduce runs it as a
// tree, so rank 0 receives about two layers' worth of pixels whatever the number of ranks.
//
// In three calls, so that every rank makes the same MPI calls whatever fails: the constructor
// (which may throw, inside an MpiWorld::step), reduce() (collective, never throws), then, once
// the ranks have agreed that every reduce() succeeded, composite_into() on rank 0.
#include <cstdint>
#include <vector>

#include "mpi/mpi_world.h"
#include "mvox/zbuffer_renderer.h"

namespace mvox {

class PictureLayer;
class SurfacePicture;

class PictureReduction {
 public:
  // A pixel as it travels between ranks.
  struct Fragment {
    float depth;
    std::uint32_t tag;  // the rank that drew it
    std::uint8_t shade;
    std::uint8_t padding[3];
  };
  // Memory a rank takes for a width x height picture: its fragments and, on rank 0, the
  // result and its copy into the picture's arrays; MPI's own buffers for the tree come on top,
  // about one more array of fragments.
  static std::uint64_t bytes(std::uint32_t width, std::uint32_t height);

  // This rank's fragments from `layer` (null for a rank without slices: nothing drawn).
  PictureReduction(const MpiWorld& world, const PictureLayer* layer, std::uint32_t width,
                   std::uint32_t height);

  // Collective: the fragments and the layers' counters reduced to rank 0. MPI's error code.
  int reduce();

  // Rank 0, after reduce() succeeded on every rank: the composited pixels into `picture`, the
  // summed counters into `counters`. Throws mvox::Error.
  void composite_into(SurfacePicture& picture, RenderCounters* counters) const;

 private:
  const MpiWorld& world_;
  std::size_t pixels_;
  std::vector<Fragment> mine_;
  std::vector<Fragment> together_;  // rank 0
  unsigned long long counters_[7] = {};
  unsigned long long total_[7] = {};
};

}  // namespace mvox
