#include "picture/picture_layer.h"

#include <string>

#include "error.h"

namespace mvox {

PictureLayer::PictureLayer(const Camera& camera, const Lighting& lighting, const glm::vec3& spacing,
                           const glm::vec3& origin, const VertexNormals* normals)
    : memory_((zbuffer_workspace_bytes(camera.width, camera.height) + sizeof(float) - 1) /
              sizeof(float)),
      tags_(std::size_t{camera.width} * camera.height) {
  const Status status =
      renderer_.init(memory_.data(), memory_.size() * sizeof(float), camera, lighting);
  if (status != Status::ok)
    throw Error("renderer", std::string("cannot start: ") + status_message(status));
  renderer_.tag_pixels(tags_.data());
  sink_.emplace(renderer_, spacing, origin, normals);
}

std::uint64_t PictureLayer::bytes(std::uint32_t width, std::uint32_t height) {
  return zbuffer_workspace_bytes(width, height) +
         std::uint64_t{width} * height * sizeof(std::uint32_t);
}

}  // namespace mvox
