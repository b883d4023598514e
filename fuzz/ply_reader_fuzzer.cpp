// Fuzzes the strict PLY reader (src/read/ply/ply_reader.h) with arbitrary bytes: ASCII and binary
// headers and bodies. Properties: it refuses with a one-line error naming the file, or returns
// a mesh that keeps every promise of PlyMesh: face offsets that start at 0 and never decrease,
// every index below the vertex count, finite coordinates, and normals for all vertices or none.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "error.h"
#include "fuzz_check.h"
#include "read/ply/ply_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mvox::PlyMesh mesh;
  try {
    mesh = mvox::parse_ply(data, size, "fuzz.ply");
  } catch (const mvox::Error& e) {
    MVOX_FUZZ_CHECK(mvox::fuzz::is_one_printable_line(e.what()), e.what());
    MVOX_FUZZ_CHECK(e.subject() == "fuzz.ply", e.what());
    return 0;
  }
  MVOX_FUZZ_CHECK(!mesh.face_offsets.empty() && mesh.face_offsets.front() == 0, "offsets");
  MVOX_FUZZ_CHECK(mesh.face_offsets.back() == mesh.face_indices.size(), "last offset");
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    MVOX_FUZZ_CHECK(mesh.face_offsets[f] < mesh.face_offsets[f + 1], "face " + std::to_string(f));
  for (const std::uint32_t index : mesh.face_indices)
    MVOX_FUZZ_CHECK(index < mesh.vertex_count(), std::to_string(index));
  MVOX_FUZZ_CHECK(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size(), "normals");
  for (const auto& p : mesh.positions)
    MVOX_FUZZ_CHECK(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]), "position");
  for (const auto& n : mesh.normals)
    MVOX_FUZZ_CHECK(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]), "normal");
  return 0;
}
