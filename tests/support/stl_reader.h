#pragma once
// Test support: a strict binary STL reader written independently of mvox's writer, to check
// every STL file mvox makes.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_capture.h"

namespace mvox::test {

using Float3 = std::array<float, 3>;

struct StlTriangle {
  Float3 normal;
  std::array<Float3, 3> vertices;
  std::uint16_t attribute = 0;
};

struct StlFile {
  std::string header;  // the 80 header bytes
  std::vector<StlTriangle> triangles;
};

// Parses binary STL (little-endian). Throws std::runtime_error unless the size is exactly
// 84 + 50 * count, and for any non-finite float.
StlFile parse_stl(const std::string& bytes);
StlFile read_stl(const std::string& path);

// Empty when every triangle's normal is a unit vector (within 1e-5) pointing the way its
// winding does (the right-hand rule on its vertices), or (0, 0, 0) for a triangle without area;
// otherwise a description of the first that is not.
std::string normal_problems(const StlFile& stl);

// The triangles as an indexed mesh, vertices identified by their exact position, numbered in
// order of first appearance: for mesh_topology's checks.
Mesh welded(const StlFile& stl);

// The contents of a file, bytes as they are.
std::string read_file_bytes(const std::string& path);

}  // namespace mvox::test
