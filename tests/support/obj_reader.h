#pragma once
// Test support: a strict reader for the OBJ subset mvox writes, written independently of the
// writer, to check every OBJ file mvox makes.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_capture.h"

namespace mvox::test {

struct ObjFile {
  std::vector<std::string> comments;  // text after "# ", in order
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 3>> normals;
  std::vector<std::vector<std::uint32_t>> faces;         // 0-based vertex indices
  std::vector<std::vector<std::uint32_t>> face_normals;  // 0-based, one per corner, or empty
  bool comments_first = true;  // no comment after the first v, vn or f line
};

// Parses OBJ text in which every line is one of
//   # TEXT | v X Y Z | vn X Y Z | f I J K ... | f I//N J//N K//N ...
// with every line ending in '\n', single spaces between fields, finite floats, and 1-based
// indices of vertices (and normals) that came before the face (a streaming writer puts them
// first). A face has at least 3 corners, all in one form. Anything else throws
// std::runtime_error naming the line.
ObjFile parse_obj(const std::string& text);
ObjFile read_obj(const std::string& path);

// The vertices and faces as a Mesh, for mesh_topology's checks.
Mesh to_mesh(const ObjFile& obj);

}  // namespace mvox::test
