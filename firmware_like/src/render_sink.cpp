#include "mvox/render_sink.h"

namespace mvox {

void volume_bounds(const VolumeInfo& volume, glm::vec3* box_min, glm::vec3* box_max) {
  const double extent[3] = {double(volume.width), double(volume.height), double(volume.depth)};
  for (int axis = 0; axis < 3; ++axis) {
    const double last = extent[axis] > 0 ? extent[axis] - 0.5 : 0.5;
    (*box_min)[axis] = static_cast<float>(volume.origin[axis] - 0.5 * volume.spacing[axis]);
    (*box_max)[axis] = static_cast<float>(volume.origin[axis] + last * volume.spacing[axis]);
  }
}

RenderSink::RenderSink(ZBufferRenderer& renderer, const glm::vec3& spacing, const glm::vec3& origin,
                       const VertexNormals* normals)
    : renderer_(renderer), spacing_(spacing), origin_(origin), normals_(normals) {}

Status RenderSink::consume_polygon_geometry(const PolygonGeometry* polygons,
                                            std::size_t polygon_count) {
  glm::vec3 positions[kMaxPolygonVertices];
  glm::vec3 normals[kMaxPolygonVertices];
  for (std::size_t p = 0; p < polygon_count; ++p) {
    const PolygonGeometry& polygon = polygons[p];
    const int count = polygon.vertex_count;
    for (int i = 0; i < count; ++i) {
      const Vertex& v = polygon.vertices[i];
      positions[i] = origin_ + spacing_ * glm::vec3(v.x, v.y, v.z);
    }
    // Normals cost more than the test, and most polygons change no pixel.
    if (!renderer_.project_polygon(positions, count)) continue;
    if (normals_) normals_->compute(polygon.vertices, static_cast<std::size_t>(count), normals);
    renderer_.draw_projected(normals_ ? normals : nullptr);
  }
  return Status::ok;
}

}  // namespace mvox
