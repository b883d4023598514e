#pragma once
// One worker's (or one rank's) share of a picture drawn in parallel: a renderer of its own with
// the picture's camera and lighting, whose pixels remember the slab that drew them, so that the
// layers can be composited into the one engine's picture (ZBufferRenderer::composite).
#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <vector>

#include "mvox/camera.h"
#include "mvox/render_sink.h"
#include "mvox/vertex_normals.h"
#include "mvox/zbuffer_renderer.h"

namespace mvox {

// A renderer of its own for one worker of a slab-parallel run (SurfacePicture::new_layer): the
// picture's camera, lighting and placement, drawing the slabs the worker takes, each tagged
// with its slab number, to be composited into the picture at the end.
class PictureLayer {
 public:
  PictureLayer(const Camera& camera, const Lighting& lighting, const glm::vec3& spacing,
               const glm::vec3& origin, const VertexNormals* normals);
  PictureLayer(const PictureLayer&) = delete;
  PictureLayer& operator=(const PictureLayer&) = delete;

  PolygonSink& sink() { return *sink_; }
  // The polygons from here on are slab `slab`'s.
  void start_slab(std::uint32_t slab) { renderer_.set_tag(slab); }
  const ZBufferRenderer& renderer() const { return renderer_; }
  // The memory a layer of width x height pixels takes: the renderer's workspace and the tags.
  static std::uint64_t bytes(std::uint32_t width, std::uint32_t height);

 private:
  std::vector<float> memory_;
  std::vector<std::uint32_t> tags_;
  ZBufferRenderer renderer_;
  std::optional<RenderSink> sink_;
};

}  // namespace mvox
