#pragma once
// Test support: the invariants every surface mvox emits must satisfy.
#include <cstdint>
#include <string>

#include "mesh_capture.h"

namespace mvox::test {

struct Topology {
  std::size_t vertices = 0;
  std::size_t edges = 0;  // undirected
  std::size_t faces = 0;
  std::size_t open_edges = 0;      // directed edges whose reverse is missing
  std::size_t repeated_edges = 0;  // directed edges used more than once (bad winding)
  std::size_t unused_vertices = 0;
  std::size_t duplicate_positions = 0;
  std::size_t degenerate_polygons = 0;  // < 3 vertices, > 7, or a vertex repeated
  std::size_t components = 0;           // connected through polygon edges
  double signed_volume = 0;             // positive when wound counter-clockwise from outside
  std::int64_t euler() const {
    return static_cast<std::int64_t>(vertices) - static_cast<std::int64_t>(edges) +
           static_cast<std::int64_t>(faces);
  }
  // Closed, every edge in exactly two faces with opposite directions, nothing degenerate.
  bool closed_and_consistent() const {
    return open_edges == 0 && repeated_edges == 0 && unused_vertices == 0 &&
           duplicate_positions == 0 && degenerate_polygons == 0;
  }
};

Topology analyse(const Mesh& mesh);

std::string describe(const Topology& topology);  // for assertion messages

}  // namespace mvox::test
