#pragma once
// Smooth per-vertex normals from the density gradient, as classic surface extraction does
// (Lorensen and Cline, 1987): central differences at the two voxels a vertex lies between,
// interpolated to where the vertex sits between them (averaged, for a midpoint). Reads the samples
// kept by a SliceWindow; allocates nothing.
#include <cstddef>
#include <glm/vec3.hpp>

#include "mvox/mesh.h"
#include "mvox/slice_window.h"

namespace mvox {

class VertexNormals {
 public:
  // `window` is borrowed and must hold slices z - 2 .. z + 1 (or up to the last slice) while
  // the vertices the engine emits for slice z are asked about (slice_window.h). `spacing` is
  // the voxel size along x, y, z in world units (> 0): gradients are taken per world unit, so
  // anisotropic voxels get the right normals.
  VertexNormals(const SliceWindow& window, const glm::vec3& spacing);

  // The outward unit normal (from inner to outer) at `vertex`, in world axes: minus the
  // density gradient. A vertex between a voxel and the outside of the volume gets the outward
  // axis direction (the surface there is a flat cap), and so does a vertex where the gradient
  // vanishes (a flat neighbourhood, as in some binary volumes).
  glm::vec3 operator()(const Vertex& vertex) const;

  // The same for `vertex_count` vertices, the sample type dispatched once for the batch.
  void compute(const Vertex* vertices, std::size_t vertex_count, glm::vec3* normals) const;

 private:
  const SliceWindow& window_;
  glm::vec3 inverse_double_spacing_;  // 1 / (2 * spacing): central differences per world unit
};

}  // namespace mvox
