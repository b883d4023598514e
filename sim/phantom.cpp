#include "phantom.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace mvox::sim {

Point3 grid_centre(const Grid& grid) {
  return {(grid.width - 1.0) / 2, (grid.height - 1.0) / 2, (grid.depth - 1.0) / 2};
}

std::uint32_t min_dimension(const Grid& grid) {
  return std::min({grid.width, grid.height, grid.depth});
}

void check_grid(const Grid& grid, const char* phantom_name) {
  if (min_dimension(grid) == 0) {
    throw std::invalid_argument(std::string(phantom_name) + ": grid " + std::to_string(grid.width) +
                                "x" + std::to_string(grid.height) + "x" +
                                std::to_string(grid.depth) + " has an empty dimension");
  }
}

std::vector<float> sample_volume(const Phantom& phantom) {
  const Grid grid = phantom.grid();
  std::vector<float> volume(std::size_t{grid.width} * grid.height * grid.depth);
  std::size_t index = 0;
  for (std::uint32_t z = 0; z < grid.depth; ++z) {
    for (std::uint32_t y = 0; y < grid.height; ++y) {
      for (std::uint32_t x = 0; x < grid.width; ++x) volume[index++] = phantom.density(x, y, z);
    }
  }
  return volume;
}

}  // namespace mvox::sim
