#include "whole_volume_reference.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "cube_merge.h"

namespace mvox::test {
namespace {

using CubeKey = std::tuple<std::int64_t, std::int64_t, std::int64_t>;  // (cz, cy, cx)

// Cube (cx, cy, cz) holds voxels cx-1..cx, cy-1..cy, cz-1..cz: corner bits b mean voxel c-1+b.
std::array<float, 3> edge_midpoint(const CubeKey& key, int e) {
  const auto [cz, cy, cx] = key;
  const int lo = cube::edge_low_corner(e), hi = cube::edge_high_corner(e);
  auto coordinate = [&](std::int64_t c, int axis) {
    return static_cast<float>(c - 1) +
           0.5f * static_cast<float>(cube::corner_bit(lo, axis) + cube::corner_bit(hi, axis));
  };
  return {coordinate(cx, 0), coordinate(cy, 1), coordinate(cz, 2)};
}

}  // namespace

Mesh whole_volume_reference(const BinaryVolume& volume) {
  auto inner = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return x >= 0 && y >= 0 && z >= 0 && x < volume.width && y < volume.height &&
           z < volume.depth &&
           volume.at(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                     static_cast<std::uint32_t>(z)) != 0;
  };
  std::map<CubeKey, CubeSurface> cubes;

  // PHASE 1 for the whole volume.
  for (std::int64_t z = 0; z < volume.depth; ++z)
    for (std::int64_t y = 0; y < volume.height; ++y)
      for (std::int64_t x = 0; x < volume.width; ++x)
        if (inner(x, y, z))
          for (int corner = 0; corner < cube::kCorners; ++corner)
            add_octant_triangle(
                cubes[{z + 1 - cube::corner_bit(corner, 2), y + 1 - cube::corner_bit(corner, 1),
                       x + 1 - cube::corner_bit(corner, 0)}],
                corner);

  // PHASE 2: the x pass over every voxel pair of the volume, then y, then z. The pair's vertex
  // lies on one edge of each of the four cubes around it.
  for (int axis = 0; axis < 3; ++axis)
    for (std::int64_t z = 0; z < volume.depth; ++z)
      for (std::int64_t y = 0; y < volume.height; ++y)
        for (std::int64_t x = 0; x < volume.width; ++x) {
          const std::int64_t step[3] = {axis == 0, axis == 1, axis == 2};
          if (!inner(x, y, z) || !inner(x + step[0], y + step[1], z + step[2])) continue;
          for (int corner = 0; corner < cube::kCorners; ++corner) {
            if (cube::corner_bit(corner, axis))
              continue;  // the pair's lower voxel is corner's low end
            const CubeKey key{z + 1 - cube::corner_bit(corner, 2),
                              y + 1 - cube::corner_bit(corner, 1),
                              x + 1 - cube::corner_bit(corner, 0)};
            merge_at_edge(cubes[key], cube::edge_from_corner(corner, axis));
          }
        }

  Mesh mesh;
  std::map<std::array<float, 3>, std::uint32_t> index_of;
  for (const auto& [key, surface] : cubes) {
    const CubePolygons polygons = extract_loops(surface);
    int offset = 0;
    for (int p = 0; p < polygons.polygon_count; ++p) {
      std::vector<std::uint32_t> indices;
      for (int i = 0; i < polygons.polygon_sizes[p]; ++i) {
        const auto position = edge_midpoint(key, polygons.edges[offset + i]);
        auto [it, added] =
            index_of.try_emplace(position, static_cast<std::uint32_t>(mesh.vertices.size()));
        if (added) {
          Vertex v;
          v.x = position[0];
          v.y = position[1];
          v.z = position[2];
          mesh.vertices.push_back(v);
        }
        indices.push_back(it->second);
      }
      offset += polygons.polygon_sizes[p];
      mesh.polygons.push_back(std::move(indices));
    }
  }
  return mesh;
}

std::vector<CanonicalPolygon> canonical_form(const Mesh& mesh) {
  std::vector<CanonicalPolygon> polygons;
  for (const auto& indices : mesh.polygons) {
    CanonicalPolygon polygon;
    for (std::uint32_t i : indices) {
      const Vertex& v = mesh.vertices.at(i);
      polygon.push_back({v.x, v.y, v.z});
    }
    std::rotate(polygon.begin(), std::min_element(polygon.begin(), polygon.end()), polygon.end());
    polygons.push_back(std::move(polygon));
  }
  std::sort(polygons.begin(), polygons.end());
  return polygons;
}

}  // namespace mvox::test
