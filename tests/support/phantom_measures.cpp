#include "phantom_measures.h"

#include <queue>

namespace mvox::test {

using sim::Grid;

std::size_t index_of(const Grid& g, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return x + std::size_t{g.width} * (y + std::size_t{g.height} * z);
}

std::size_t count_at_least(const std::vector<float>& volume, float threshold) {
  std::size_t count = 0;
  for (float d : volume) count += d >= threshold;
  return count;
}

int count_components(const Grid& g, const std::vector<float>& volume, float threshold) {
  std::vector<char> seen(volume.size(), 0);
  int components = 0;
  for (std::size_t start = 0; start < volume.size(); ++start) {
    if (seen[start] || volume[start] < threshold) continue;
    ++components;
    std::queue<std::size_t> queue;
    queue.push(start);
    seen[start] = 1;
    while (!queue.empty()) {
      const std::size_t i = queue.front();
      queue.pop();
      const std::uint32_t x = i % g.width;
      const std::uint32_t y = (i / g.width) % g.height;
      const std::uint32_t z = static_cast<std::uint32_t>(i / (std::size_t{g.width} * g.height));
      auto visit = [&](bool inside, std::size_t j) {
        if (inside && !seen[j] && volume[j] >= threshold) {
          seen[j] = 1;
          queue.push(j);
        }
      };
      visit(x > 0, i - 1);
      visit(x + 1 < g.width, i + 1);
      visit(y > 0, i - g.width);
      visit(y + 1 < g.height, i + g.width);
      visit(z > 0, i - std::size_t{g.width} * g.height);
      visit(z + 1 < g.depth, i + std::size_t{g.width} * g.height);
    }
  }
  return components;
}

long euler_characteristic(const Grid& g, const std::vector<float>& volume, float threshold) {
  auto in = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) -> long {
    if (x >= g.width || y >= g.height || z >= g.depth) return 0;
    return volume[index_of(g, x, y, z)] >= threshold;
  };
  long chi = 0;
  for (std::uint32_t z = 0; z < g.depth; ++z)
    for (std::uint32_t y = 0; y < g.height; ++y)
      for (std::uint32_t x = 0; x < g.width; ++x) {
        if (!in(x, y, z)) continue;
        const long ex = in(x + 1, y, z), ey = in(x, y + 1, z), ez = in(x, y, z + 1);
        const long sxy = ex && ey && in(x + 1, y + 1, z);
        const long sxz = ex && ez && in(x + 1, y, z + 1);
        const long syz = ey && ez && in(x, y + 1, z + 1);
        const long cube = sxy && sxz && syz && in(x + 1, y + 1, z + 1);
        chi += 1 - (ex + ey + ez) + (sxy + sxz + syz) - cube;
      }
  return chi;
}

}  // namespace mvox::test
