#pragma once
// A strict PLY reader: any malformed input is refused with an mvox::Error, never guessed at.
// It lives in the host library because mvox reads meshes back: the tests check every file the
// writer makes with it, and `mvox render mesh.ply` and the fuzz targets (planned) will use it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mvox {

// A polygon mesh in flat arrays. Face i has the vertex indices
// face_indices[face_offsets[i]] .. face_indices[face_offsets[i + 1] - 1];
// face_offsets has face_count() + 1 entries and starts with 0. Every index is < vertex_count().
struct PlyMesh {
  std::vector<std::array<float, 3>> positions;
  // One per vertex when the file has scalar properties nx, ny and nz; otherwise empty.
  std::vector<std::array<float, 3>> normals;
  std::vector<std::uint32_t> face_offsets = {0};
  std::vector<std::uint32_t> face_indices;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return face_offsets.size() - 1; }
};

// Reads the PLY file at `path` into memory and parses it with parse_ply().
// Throws mvox::Error naming `path` ("mesh.ply: cannot open file: No such file or directory").
PlyMesh read_ply(const std::string& path);

// Parses a whole PLY file held in `data` (`size` bytes; need not be null-terminated).
// Accepted: format ascii, binary_little_endian or binary_big_endian 1.0; an element "vertex"
// with scalar properties x, y and z of any type (converted to float), and optionally nx, ny
// and nz (read as normals when all three are there; other properties, lists included, are
// skipped); an optional element "face" with an integer list property
// "vertex_indices" or "vertex_index" (other properties skipped); any other elements, skipped.
// Refused with mvox::Error(name_for_errors, problem): a missing "ply" line, a bad or missing
// format line, unknown header keywords or types, duplicate elements or properties, element
// counts that the remaining bytes cannot hold (checked before anything is allocated, so memory
// stays within a small multiple of `size`), truncated data, ASCII lines with too few or too
// many values, numbers that do not fit their declared type, non-finite or out-of-float-range
// coordinates, faces with 0 vertices, vertex indices that are negative or >= the vertex count,
// and any bytes after the last element (ASCII: anything but white space).
// Never reads outside [data, data + size).
PlyMesh parse_ply(const void* data, std::size_t size, const std::string& name_for_errors);

}  // namespace mvox
