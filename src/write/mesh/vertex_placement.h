#pragma once
// Where a vertex lands in a written mesh: its world position through the placement (spacing,
// origin, axes) and its normal turned into world axes. MeshWriter places every batch it is
// given; slab workers place their own batches before the writer takes them
// (pipeline/slab_recorder.h), so that this work runs in parallel, with the same floats.
#include <cstddef>
#include <glm/vec3.hpp>

#include "mvox/mesh.h"
#include "write/mesh/world_transform.h"

namespace mvox {

// A vertex as written: its world position, and its world normal when the mesh has normals.
struct WorldVertex {
  float position[3] = {};
  float normal[3] = {};
};

// Immutable once made: any number of threads may place with one.
class VertexPlacement {
 public:
  // `transform` must pass its check(). `with_normals`: place() takes and turns normals.
  VertexPlacement(const WorldTransform& transform, bool with_normals);

  // Places `count` vertices into `out`, with `normals` (one per vertex, in the spaced voxel
  // frame, as VertexNormals computes them) when with_normals. Returns the index of the first
  // vertex whose position leaves float's range (converting it would be undefined behaviour),
  // whose place and those after it are unspecified, or `count` when every one fits.
  std::size_t place(const Vertex* vertices, const glm::vec3* normals, std::size_t count,
                    WorldVertex* out) const;
  // The positions alone, as the records of a binary format without normals: x, y, z as
  // little-endian floats, 12 bytes a vertex, the same floats place() gives. `out` must have
  // room for count * 12 + kPositionSlack bytes (each vertex may be stored as 16). Returns count,
  // or the index of the first vertex whose position leaves float's range (the records are then
  // unspecified). Only without normals.
  static constexpr std::size_t kPositionSlack = 4;
  std::size_t place_positions(const Vertex* vertices, std::size_t count, unsigned char* out) const;

  bool with_normals() const { return with_normals_; }

 private:
  // The vertex's world position as WorldTransform computes it, rounded to floats, or false when
  // a coordinate leaves float's range (its conversion would be undefined behaviour).
  bool world_floats(const Vertex& vertex, float position[3]) const;

  WorldTransform transform_;
  bool axis_aligned_;
  bool identity_;  // axis-aligned, spacing 1, origin +0
  Matrix3d normal_matrix_;
  bool with_normals_;
};

}  // namespace mvox
