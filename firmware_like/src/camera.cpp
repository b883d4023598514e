#include "mvox/camera.h"

#include <algorithm>
#include <cmath>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

namespace mvox {

glm::mat3 view_rotation(const ViewOptions& view) {
  // Camera frame at the default view, as world vectors: right = +x, up = +z, and "back" (from
  // the box towards the camera) = -y. Columns of a camera-to-world rotation.
  const glm::mat3 base(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, -1, 0));
  const glm::mat4 identity(1.0f);
  // Elevation tilts the back vector from -y towards +z: a rotation about x by -elevation.
  const glm::mat3 elevate(
      glm::rotate(identity, glm::radians(-view.elevation_deg), glm::vec3(1, 0, 0)));
  const glm::mat3 turn(glm::rotate(identity, glm::radians(view.azimuth_deg), glm::vec3(0, 0, 1)));
  // Roll turns the picture counter-clockwise: the camera turns clockwise about its back axis.
  const glm::mat3 roll(glm::rotate(identity, glm::radians(-view.roll_deg), glm::vec3(0, 0, 1)));
  const glm::mat3 camera_to_world = turn * elevate * base * roll;
  return glm::transpose(camera_to_world);
}

Camera fit_camera(const glm::vec3& box_min, const glm::vec3& box_max, const ViewOptions& view,
                  std::uint32_t width, std::uint32_t height) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.world_to_view = view_rotation(view);
  const glm::vec3 centre = 0.5f * (box_min + box_max);
  const float aspect =
      static_cast<float>(width) / static_cast<float>(std::max<std::uint32_t>(height, 1));
  const float fill = std::max(0.05f, 1.0f - 2.0f * view.margin);  // image fraction to use

  glm::mat4 view_matrix(camera.world_to_view);  // rotation about the box centre
  view_matrix = view_matrix * glm::translate(glm::mat4(1.0f), -centre);

  // Extents of the eight rotated corners: the projection of the box, and its depth.
  glm::vec3 extent(0.0f);
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? box_max.x : box_min.x, (corner & 2) ? box_max.y : box_min.y,
                      (corner & 4) ? box_max.z : box_min.z);
    extent = glm::max(extent, glm::abs(camera.world_to_view * (p - centre)));
  }

  if (!view.perspective) {
    // Half the image height in world units, so that both extents fit.
    float half_height = std::max(extent.y, extent.x / aspect) / fill;
    if (!(half_height > 0.0f)) half_height = 1.0f;
    const float depth = std::max(extent.z, 1e-3f) * 1.01f + 1e-3f;
    camera.world_to_clip = glm::ortho(-half_height * aspect, half_height * aspect, -half_height,
                                      half_height, -depth, depth) *
                           view_matrix;
  } else {
    float radius = 0.5f * glm::length(box_max - box_min);
    if (!(radius > 0.0f)) radius = 1.0f;
    const float fov = glm::radians(std::clamp(view.field_of_view_deg, 1.0f, 170.0f));
    // The sphere fits when its angular radius is half the (narrower) field of view, shrunk by
    // the margin.
    const float half_fov = std::atan(std::tan(0.5f * fov) * std::min(1.0f, aspect) * fill);
    const float distance = radius / std::sin(half_fov);
    const glm::mat4 back_off = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -distance));
    const float near_plane = std::max(distance - radius * 1.01f, distance * 1e-3f);
    const float far_plane = distance + radius * 1.01f;
    camera.world_to_clip =
        glm::perspective(fov, aspect, near_plane, far_plane) * back_off * view_matrix;
  }
  if (view.cut > 0.0f) {
    // The plane `cut` of the way from the box's nearest corner to its farthest (view space looks
    // along -z, so the nearest corner is at +extent.z), projected like any point.
    const float plane_z = extent.z * (1.0f - 2.0f * std::min(view.cut, 1.0f));
    const glm::vec3 on_plane = centre + glm::transpose(camera.world_to_view) * glm::vec3(0, 0, plane_z);
    const glm::vec4 clip = camera.world_to_clip * glm::vec4(on_plane, 1.0f);
    // Above 0, so that a cut always reads as one, even at the box's very front.
    camera.cut_depth = std::max(0.5f * (clip.z / clip.w + 1.0f), 1e-7f);
  }
  return camera;
}

}  // namespace mvox
