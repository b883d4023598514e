#include "mpi/picture_reduction.h"

#include <limits>

#include "error.h"
#include "picture/picture_layer.h"
#include "picture/surface_picture.h"

namespace mvox {
namespace {

using Fragment = PictureReduction::Fragment;

// MPI's user function: `into` keeps the lower of (depth, tag), as composite_pixels() does.
void keep_nearest(void* from, void* into, int* count, MPI_Datatype*) {
  const auto* in = static_cast<const Fragment*>(from);
  auto* out = static_cast<Fragment*>(into);
  for (int i = 0; i < *count; ++i) {
    const float d = in[i].depth;
    if (d < out[i].depth || (d == out[i].depth && in[i].tag < out[i].tag &&
                             d != std::numeric_limits<float>::infinity()))
      out[i] = in[i];
  }
}

}  // namespace

std::uint64_t PictureReduction::bytes(std::uint32_t width, std::uint32_t height) {
  const std::uint64_t pixels = std::uint64_t{width} * height;
  return pixels * (2 * sizeof(Fragment) + sizeof(float) + 1 + sizeof(std::uint32_t));
}

PictureReduction::PictureReduction(const MpiWorld& world, const PictureLayer* layer,
                                   std::uint32_t width, std::uint32_t height)
    : world_(world),
      pixels_(std::size_t{width} * height),
      mine_(pixels_, Fragment{std::numeric_limits<float>::infinity(), 0, 0, {}}),
      together_(world.rank() == 0 ? pixels_ : 0) {
  if (!layer) return;
  const ZBufferRenderer& renderer = layer->renderer();
  for (std::size_t i = 0; i < pixels_; ++i)
    mine_[i] = {
        renderer.depths()[i], static_cast<std::uint32_t>(world.rank()), renderer.pixels()[i], {}};
  const RenderCounters& c = renderer.counters();
  const unsigned long long counters[7] = {
      c.polygons,        c.polygons_clipped,  c.triangles_culled, c.triangles_hidden,
      c.triangles_drawn, c.fragments_covered, c.fragments_written};
  for (int i = 0; i < 7; ++i) counters_[i] = counters[i];
}

int PictureReduction::reduce() {
  MPI_Datatype fragment;
  int code = MPI_Type_contiguous(sizeof(Fragment), MPI_BYTE, &fragment);
  if (code == MPI_SUCCESS) code = MPI_Type_commit(&fragment);
  MPI_Op nearest;
  const int op = MPI_Op_create(&keep_nearest, 1, &nearest);
  // Both reductions are made whatever came before, so that no rank waits for another alone.
  const int pixels = MPI_Reduce(mine_.data(), together_.data(), static_cast<int>(pixels_),
                                code == MPI_SUCCESS ? fragment : MPI_BYTE,
                                op == MPI_SUCCESS ? nearest : MPI_MIN, 0, world_.comm());
  const int counters =
      MPI_Reduce(counters_, total_, 7, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, world_.comm());
  if (op == MPI_SUCCESS) MPI_Op_free(&nearest);
  if (code == MPI_SUCCESS) MPI_Type_free(&fragment);
  for (const int result : {code, op, pixels, counters})
    if (result != MPI_SUCCESS) return result;
  return MPI_SUCCESS;
}

void PictureReduction::composite_into(SurfacePicture& picture, RenderCounters* counters) const {
  std::vector<float> depth(pixels_);
  std::vector<std::uint8_t> shade(pixels_);
  std::vector<std::uint32_t> tags(pixels_);
  for (std::size_t i = 0; i < pixels_; ++i) {
    depth[i] = together_[i].depth;
    shade[i] = together_[i].shade;
    tags[i] = together_[i].tag;
  }
  picture.composite(depth.data(), shade.data(), tags.data());
  *counters = {total_[0], total_[1], total_[2], total_[3], total_[4], total_[5], total_[6]};
}

}  // namespace mvox
