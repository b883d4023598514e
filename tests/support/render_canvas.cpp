#include "render_canvas.h"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

namespace mvox::test {

Camera pixel_camera(std::uint32_t width, std::uint32_t height) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  glm::mat4 m(1.0f);  // glm is column-major: m[column][row]
  m[0][0] = 2.0f / static_cast<float>(width);
  m[3][0] = -1.0f;
  m[1][1] = -2.0f / static_cast<float>(height);
  m[3][1] = 1.0f;
  camera.world_to_clip = m;
  camera.world_to_view = glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, -1));
  return camera;
}

glm::vec3 to_world(const Sub& p, float z) {
  return {static_cast<float>(p.x) / kSubpixel, static_cast<float>(p.y) / kSubpixel, z};
}

std::int64_t cross(const Sub& o, const Sub& a, const Sub& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

std::vector<glm::vec3> world_polygon(const std::vector<Sub>& points, float z) {
  std::vector<glm::vec3> out;
  for (const Sub& p : points) out.push_back(to_world(p, z));
  return out;
}

Lighting no_culling() {
  Lighting lighting;
  lighting.cull_back_faces = false;
  return lighting;
}

}  // namespace mvox::test
