#pragma once
// The renderer as a polygon sink: the engine's polygons (run it with
// EngineOptions::polygon_geometry) drawn as each layer of cubes completes, so the picture grows
// with the scan. Allocates nothing; keeps nothing per vertex.
#include <cstddef>
#include <glm/vec3.hpp>

#include "mvox/polygon_sink.h"
#include "mvox/slice_source.h"
#include "mvox/vertex_normals.h"
#include "mvox/zbuffer_renderer.h"

namespace mvox {

// The world box the surface of a width x height x depth volume can occupy: voxel coordinates
// -0.5 .. n - 0.5 on each axis (vertices lie half-way to the outside), times the spacing, plus
// the origin. For fit_camera().
void volume_bounds(const VolumeInfo& volume, glm::vec3* box_min, glm::vec3* box_max);

class RenderSink final : public PolygonSink {
 public:
  // All borrowed. Vertices are placed at origin + spacing * voxel coordinate, like the mesh
  // writer's. `normals` gives smooth shading; with nullptr each triangle is shaded flat.
  RenderSink(ZBufferRenderer& renderer, const glm::vec3& spacing, const glm::vec3& origin,
             const VertexNormals* normals);

  Status consume_vertices(const Vertex*, std::size_t) override { return Status::ok; }
  Status consume_polygons(const Polygon*, std::size_t) override { return Status::ok; }
  Status consume_polygon_geometry(const PolygonGeometry* polygons,
                                  std::size_t polygon_count) override;

 private:
  ZBufferRenderer& renderer_;
  glm::vec3 spacing_;
  glm::vec3 origin_;
  const VertexNormals* normals_;
};

}  // namespace mvox
