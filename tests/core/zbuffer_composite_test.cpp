// Sort-last compositing (ZBufferRenderer::composite): a picture drawn in parts by several
// renderers, each tagging its pixels with its part's number, composites into the picture one
// renderer draws from all the parts in order, bit for bit: depths and shades, ties in depth
// going to the earlier part, in whatever order the renderers are composited.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "mvox/zbuffer_renderer.h"
#include "render_canvas.h"

namespace mvox {
namespace {

using test::Canvas;
using test::pixel_camera;

struct Shape {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
};

// Random triangles and quads over a 64x64 screen at depths across the range; every fifth one
// again in a later part with other normals, at exactly the same place: equal depths in two
// parts, where the earlier part must win.
std::vector<std::vector<Shape>> random_parts(int parts, int shapes_per_part, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> xy(-4.0f, 68.0f), z(-0.9f, 0.9f), n(-1.0f, 1.0f);
  std::vector<std::vector<Shape>> result(parts);
  std::vector<Shape> repeated;
  for (int part = 0; part < parts; ++part) {
    for (int i = 0; i < shapes_per_part; ++i) {
      Shape shape;
      const int corners = 3 + static_cast<int>(random() % 2);
      for (int k = 0; k < corners; ++k) {
        shape.positions.push_back({xy(random), xy(random), z(random)});
        shape.normals.push_back({n(random), n(random), -1.0f});
      }
      if (i % 5 == 0) repeated.push_back(shape);
      result[part].push_back(shape);
    }
    // The repeats of earlier parts, with other normals: equal depth, another shade.
    for (Shape& shape : repeated)
      for (glm::vec3& normal : shape.normals) normal = {n(random), n(random), -0.5f};
    if (part + 1 < parts)
      for (const Shape& shape : repeated) result[part + 1].push_back(shape);
    repeated.clear();
  }
  return result;
}

void draw(Canvas& canvas, const std::vector<Shape>& shapes) {
  for (const Shape& shape : shapes) canvas.draw(shape.positions, &shape.normals);
}

TEST(ZBufferComposite, PartsDrawnApartCompositeIntoThePictureOneRendererDraws) {
  const Camera camera = pixel_camera(64, 64);
  for (const int layers : {2, 3, 5}) {
    SCOPED_TRACE("layers " + std::to_string(layers));
    const auto parts = random_parts(12, 40, 17u + layers);
    Canvas one(camera, test::no_culling());
    for (const auto& part : parts) draw(one, part);

    // Part p goes to layer p % layers, as slabs go to workers.
    std::vector<std::unique_ptr<Canvas>> canvases;
    std::vector<std::vector<std::uint32_t>> tags(layers, std::vector<std::uint32_t>(64 * 64));
    for (int l = 0; l < layers; ++l) {
      canvases.push_back(std::make_unique<Canvas>(camera, test::no_culling()));
      canvases[l]->renderer.tag_pixels(tags[l].data());
    }
    for (std::size_t p = 0; p < parts.size(); ++p) {
      Canvas& canvas = *canvases[p % layers];
      canvas.renderer.set_tag(static_cast<std::uint32_t>(p));
      draw(canvas, parts[p]);
    }
    // Composited backwards, into a fresh renderer that drew nothing.
    Canvas together(camera, test::no_culling());
    std::vector<std::uint32_t> together_tags(64 * 64);
    together.renderer.tag_pixels(together_tags.data());
    for (int l = layers - 1; l >= 0; --l)
      ASSERT_EQ(together.renderer.composite(canvases[l]->renderer), Status::ok);
    EXPECT_EQ(std::memcmp(together.renderer.depths(), one.renderer.depths(), 64 * 64 * 4), 0);
    EXPECT_EQ(std::memcmp(together.renderer.pixels(), one.renderer.pixels(), 64 * 64), 0);
    EXPECT_EQ(together.renderer.counters().polygons, one.renderer.counters().polygons);
  }
}

TEST(ZBufferComposite, EqualDepthsGoToTheEarlierPart) {
  // The tie rule matters: with the later part winning ties, the pictures differ.
  const Camera camera = pixel_camera(64, 64);
  const auto parts = random_parts(2, 40, 5u);
  Canvas one(camera, test::no_culling());
  for (const auto& part : parts) draw(one, part);
  Canvas late_first(camera, test::no_culling());
  draw(late_first, parts[1]);
  draw(late_first, parts[0]);
  ASSERT_NE(std::memcmp(late_first.renderer.pixels(), one.renderer.pixels(), 64 * 64), 0)
      << "the parts never tie: the test would not see the tie rule";

  Canvas first(camera, test::no_culling()), second(camera, test::no_culling());
  std::vector<std::uint32_t> tags_first(64 * 64), tags_second(64 * 64);
  first.renderer.tag_pixels(tags_first.data());
  second.renderer.tag_pixels(tags_second.data());
  first.renderer.set_tag(0);
  draw(first, parts[0]);
  second.renderer.set_tag(1);
  draw(second, parts[1]);
  ASSERT_EQ(second.renderer.composite(first.renderer), Status::ok);
  EXPECT_EQ(std::memcmp(second.renderer.pixels(), one.renderer.pixels(), 64 * 64), 0);
}

TEST(ZBufferComposite, RefusesRenderersWithoutTagsOrOfAnotherSize) {
  Canvas a(pixel_camera(64, 64)), b(pixel_camera(64, 64)), c(pixel_camera(32, 64));
  EXPECT_EQ(a.renderer.composite(b.renderer), Status::invalid_argument);  // no tags
  std::vector<std::uint32_t> ta(64 * 64), tb(64 * 64), tc(32 * 64);
  a.renderer.tag_pixels(ta.data());
  b.renderer.tag_pixels(tb.data());
  c.renderer.tag_pixels(tc.data());
  EXPECT_EQ(a.renderer.composite(b.renderer), Status::ok);
  EXPECT_EQ(a.renderer.composite(c.renderer), Status::invalid_argument);
}

}  // namespace
}  // namespace mvox
