#include "phantom_factory.h"

#include <algorithm>
#include <stdexcept>

#include "random_phantoms.h"
#include "shapes.h"
#include "shepp_logan.h"

namespace mvox::sim {
namespace {

constexpr std::uint32_t kDefaultBlobCount = 64;
constexpr double kDefaultRandomInnerProbability = 0.3;

[[noreturn]] void throw_unknown(const std::string& name) {
  std::string message = "unknown phantom '" + name + "'; valid names:";
  for (const std::string& valid : phantom_names()) message += " " + valid;
  throw std::invalid_argument(message);
}

}  // namespace

const std::vector<std::string>& phantom_names() {
  static const std::vector<std::string> names = {"sphere",      "torus", "shells",
                                                 "shepp-logan", "blobs", "random"};
  return names;
}

std::unique_ptr<Phantom> make_phantom(const std::string& name, Grid grid, std::uint64_t seed) {
  const Point3 centre = grid_centre(grid);
  const double m = min_dimension(grid);
  const double mxy = std::min(grid.width, grid.height);
  if (name == "sphere") return std::make_unique<Sphere>(grid, centre, 0.4 * m);
  if (name == "torus") return std::make_unique<Torus>(grid, centre, 0.3 * mxy, 0.12 * mxy);
  if (name == "shells") {
    return std::make_unique<NestedShells>(grid, centre, std::vector<double>{0.4 * m, 0.25 * m});
  }
  if (name == "shepp-logan") return std::make_unique<SheppLogan3D>(grid);
  if (name == "blobs") return std::make_unique<RandomBlobs>(grid, seed, kDefaultBlobCount);
  if (name == "random") {
    return std::make_unique<RandomVoxels>(grid, seed, kDefaultRandomInnerProbability);
  }
  throw_unknown(name);
}

double default_density_threshold(const std::string& name) {
  // Shepp-Logan densities are 1.0 (skull), 0.2 (brain), 0.0 (ventricles) and 0.3 (the small
  // bright ellipsoids, 0.2 + 0.1). 0.25 lies halfway between brain and the bright features, so
  // the surface is the skull plus each bright feature as its own component, and the margin of
  // 0.05 on both sides survives 8-bit quantisation (0.05 * 255 = 12.75 levels).
  if (name == "shepp-logan") return 0.25;
  // Blob amplitudes are in [0.6, 1.4), so at 0.5 every blob shows as a ball and only blobs
  // that overlap merge: with the default 64 blobs, about 10 to 20 components on 64^3, some with
  // handles (checked for a few seeds in sim_test).
  if (name == "blobs") return 0.5;
  // The binary phantoms are 0 or 1: halfway is as far from both as possible.
  if (name == "sphere" || name == "torus" || name == "shells" || name == "random") return 0.5;
  throw_unknown(name);
}

}  // namespace mvox::sim
