#include "mpi/picture_reduction.h"

#include <limits>
#include <vector>

#include "error.h"
#include "picture/surface_picture.h"

namespace mvox {
namespace {

// One pixel as it travels between ranks.
struct Fragment {
  float depth;
  std::uint32_t tag;  // the rank that drew it
  std::uint8_t shade;
  std::uint8_t padding[3];
};

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

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw Error("MPI", std::string(what) + ": " + mpi_error_text(code));
}

}  // namespace

void reduce_picture(const MpiWorld& world, const PictureLayer* layer, std::uint32_t width,
                    std::uint32_t height, SurfacePicture* picture, RenderCounters* counters) {
  const std::size_t pixels = std::size_t{width} * height;
  std::vector<Fragment> mine(pixels, Fragment{std::numeric_limits<float>::infinity(), 0, 0, {}});
  RenderCounters drawn;
  if (layer) {
    const ZBufferRenderer& renderer = layer->renderer();
    for (std::size_t i = 0; i < pixels; ++i)
      mine[i] = {renderer.depths()[i], static_cast<std::uint32_t>(world.rank()),
                 renderer.pixels()[i], {}};
    drawn = renderer.counters();
  }
  MPI_Datatype fragment;
  check(MPI_Type_contiguous(sizeof(Fragment), MPI_BYTE, &fragment), "fragment type");
  MPI_Type_commit(&fragment);
  MPI_Op nearest;
  check(MPI_Op_create(&keep_nearest, 1, &nearest), "compositing operation");
  std::vector<Fragment> together(world.rank() == 0 ? pixels : 0);
  const int reduced = MPI_Reduce(mine.data(), together.data(), static_cast<int>(pixels), fragment,
                                 nearest, 0, world.comm());
  MPI_Op_free(&nearest);
  MPI_Type_free(&fragment);
  check(reduced, "compositing the picture");

  unsigned long long sums[7] = {drawn.polygons,        drawn.polygons_clipped,
                                drawn.triangles_culled, drawn.triangles_hidden,
                                drawn.triangles_drawn,  drawn.fragments_covered,
                                drawn.fragments_written};
  unsigned long long total[7] = {};
  check(MPI_Reduce(sums, total, 7, MPI_UNSIGNED_LONG_LONG, MPI_SUM, 0, world.comm()),
        "summing the picture's counters");
  if (world.rank() != 0) return;
  std::vector<float> depth(pixels);
  std::vector<std::uint8_t> shade(pixels);
  std::vector<std::uint32_t> tags(pixels);
  for (std::size_t i = 0; i < pixels; ++i) {
    depth[i] = together[i].depth;
    shade[i] = together[i].shade;
    tags[i] = together[i].tag;
  }
  picture->composite(depth.data(), shade.data(), tags.data());
  *counters = {total[0], total[1], total[2], total[3], total[4], total[5], total[6]};
}

}  // namespace mvox
