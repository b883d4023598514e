#pragma once
// A mesh kept in arrays instead of written to a file: what the PLY writer would write, vertex
// for vertex and face for face (the same placement, winding and triangulation, MeshWriter's),
// for callers that hand the mesh on in memory, such as the Python module.
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "write/mesh/growable_array.h"
#include "write/mesh/mesh_writer.h"

namespace mvox {

// Numbers grown without copying (growable_array.h).
template <class T>
using ArrayOf = GrowableArray<T>;

// Faces in the compressed-row layout of VTK's cell arrays: face i is
// polygon_indices[polygon_offsets[i] .. polygon_offsets[i + 1]).
//
// The indices are 32-bit while the mesh has at most 2^31 vertices, half the memory and the
// type most readers expect; past that they are 64-bit (`wide`): widen_indices() moves those
// held into wide_polygon_indices, which takes every index from then on.
struct MeshArrays {
  ArrayOf<float> vertices;  // x, y, z of each vertex, in the world (as PLY's x, y, z)
  ArrayOf<float> normals;   // nx, ny, nz of each vertex, when asked for; else empty
  ArrayOf<std::int64_t> polygon_offsets{0};  // one more than there are faces
  ArrayOf<std::int32_t> polygon_indices;
  ArrayOf<std::int64_t> wide_polygon_indices;
  bool wide = false;

  std::size_t vertex_count() const { return vertices.size() / 3; }
  std::size_t face_count() const { return polygon_offsets.size() - 1; }
  std::size_t index_count() const {
    return wide ? wide_polygon_indices.size() : polygon_indices.size();
  }
};

// The vertices a mesh's 32-bit signed indices reach: indices 0 to 2^31 - 1.
constexpr std::uint64_t kNarrowIndexVertices = std::uint64_t{1} << 31;

// Moves the 32-bit indices held into wide_polygon_indices, which takes every index from then on.
void widen_indices(MeshArrays& arrays);

// Appends `count` polygons to a wide mesh's offsets and indices. A polygon's slot plus
// `index_offset`, modulo 2^32 (mvox/mesh.h), is made whole among the last 2^32 of the
// `vertices_taken` vertices so far (whole_vertex_index).
void append_wide_polygons(MeshArrays& arrays, const Polygon* polygons, std::size_t count,
                          std::uint32_t index_offset, std::uint64_t vertices_taken);

// Appends `count` polygons to `arrays`' offsets and indices in one pass. Each polygon's seven
// index slots are copied whole, without a branch on its size, the next one overwriting the
// unused: the indices are first grown by seven a polygon, then cut back to what they hold.
void append_polygons(MeshArrays& arrays, const Polygon* polygons, std::size_t count);

// Appends the x, y and z of `count` engine vertices to `arrays.vertices` as they are: their
// world positions when the spacing is 1 and the origin 0. Each vertex's first 16 bytes are
// copied whole, the next one overwriting the fourth float.
void append_vertex_positions(MeshArrays& arrays, const Vertex* vertices, std::size_t count);

// Both appends are bound by their stores into megabytes of fresh memory. With AVX2 (chosen at
// run time) a polygon is one store and two vertices are one, into a small staging buffer whose
// whole 32-byte blocks go out with non-temporal stores (mesh_arrays.cpp). These are the plain
// loops: the references the fast ones are tested against, and the appends without AVX2.
void append_polygons_portable(MeshArrays& arrays, const Polygon* polygons, std::size_t count);
void append_vertex_positions_portable(MeshArrays& arrays, const Vertex* vertices,
                                      std::size_t count);

// A MeshWriter into MeshArrays. Memory grows with the mesh, as the arrays it returns must.
class MeshArraysWriter : public MeshWriter {
 public:
  // `subject` names the mesh in messages (say, "mvox.extract").
  MeshArraysWriter(const MeshWriterOptions& options, std::string subject);

  // The mesh so far; complete after finish().
  MeshArrays& arrays() { return arrays_; }
  const std::string& subject() const override { return subject_; }
  OutputFile* output_file() override { return nullptr; }

 private:
  void write_vertices(const WorldVertex* vertices, std::size_t vertex_count) override;
  void write_faces(const Polygon* faces, std::size_t face_count,
                   std::uint32_t index_offset) override;
  void complete_file() override {}

  std::string subject_;
  MeshArrays arrays_;
};

}  // namespace mvox
