#include "mesh_topology.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <tuple>

namespace mvox::test {
namespace {

std::size_t find_root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

Topology analyse(const Mesh& mesh) {
  Topology t;
  t.vertices = mesh.vertices.size();
  t.faces = mesh.polygons.size();
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  std::vector<bool> used(mesh.vertices.size(), false);
  std::vector<std::size_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});

  for (const auto& polygon : mesh.polygons) {
    std::set<std::uint32_t> distinct(polygon.begin(), polygon.end());
    if (polygon.size() < 3 || polygon.size() > 7 || distinct.size() != polygon.size()) {
      ++t.degenerate_polygons;
      continue;
    }
    const Vertex& origin = mesh.vertices.at(polygon[0]);
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const std::uint32_t a = polygon[i], b = polygon[(i + 1) % polygon.size()];
      ++directed[{a, b}];
      used.at(a) = true;
      parent[find_root(parent, a)] = find_root(parent, b);
      // Fan from vertex 0: each triangle's contribution to the enclosed volume.
      if (i >= 1 && i + 1 < polygon.size()) {
        const Vertex& p = mesh.vertices.at(a);
        const Vertex& q = mesh.vertices.at(b);
        const double cx = double(p.y) * q.z - double(p.z) * q.y;
        const double cy = double(p.z) * q.x - double(p.x) * q.z;
        const double cz = double(p.x) * q.y - double(p.y) * q.x;
        t.signed_volume += (origin.x * cx + origin.y * cy + origin.z * cz) / 6.0;
      }
    }
  }
  for (const auto& [edge, count] : directed) {
    if (count > 1) ++t.repeated_edges;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end()) ++t.open_edges;
    if (reverse == directed.end() || edge.first < edge.second) ++t.edges;
  }
  std::set<std::tuple<float, float, float>> positions;
  std::set<std::size_t> roots;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vertex& v = mesh.vertices[i];
    if (!positions.insert({v.x, v.y, v.z}).second) ++t.duplicate_positions;
    if (!used[i]) {
      ++t.unused_vertices;
      continue;
    }
    roots.insert(find_root(parent, i));
  }
  t.components = roots.size();
  return t;
}

std::string describe(const Topology& t) {
  std::ostringstream out;
  out << "V=" << t.vertices << " E=" << t.edges << " F=" << t.faces << " euler=" << t.euler()
      << " components=" << t.components << " open=" << t.open_edges
      << " repeated=" << t.repeated_edges << " unused=" << t.unused_vertices
      << " duplicate_positions=" << t.duplicate_positions << " degenerate=" << t.degenerate_polygons
      << " volume=" << t.signed_volume;
  return out.str();
}

}  // namespace mvox::test
