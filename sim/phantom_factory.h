#pragma once
// Phantoms by name, with defaults scaled to the grid: what the command line and the benchmarks
// use to say "a torus on 256^3" without knowing the constructors.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "phantom.h"

namespace mvox::sim {

// The names make_phantom accepts: "sphere", "torus", "shells", "shepp-logan", "blobs",
// "random".
const std::vector<std::string>& phantom_names();

// The phantom `name` on `grid`, centred, sized relative to the grid (m = smallest dimension,
// mxy = smaller of width and height):
//   sphere       radius 0.4 m
//   torus        axis along z, major radius 0.3 mxy, minor radius 0.12 mxy
//   shells       one hollow shell, radii 0.4 m and 0.25 m
//   shepp-logan  the modified 3-D Shepp-Logan head stretched over the grid
//   blobs        64 random Gaussian blobs from `seed` (radii 2 to 0.1 m)
//   random       independent voxels from `seed`, inner with probability 0.3
// `seed` only matters for "blobs" and "random". Throws std::invalid_argument for an unknown
// name (the message lists the valid ones) or an empty grid.
std::unique_ptr<Phantom> make_phantom(const std::string& name, Grid grid, std::uint64_t seed);

// A density threshold that shows the phantom `name` well (see phantom_factory.cpp for why).
// Throws std::invalid_argument for an unknown name.
double default_density_threshold(const std::string& name);

}  // namespace mvox::sim
