#pragma once
// The paper's third phase: polygons projected into an image through a z-buffer, Phong-shaded
// per pixel with normals interpolated across each polygon, 8-bit grayscale. Polygons can be
// drawn as they arrive, so the picture grows while a scan streams in; the image is complete
// after the last one whatever the order. Memory is the caller's (zbuffer_workspace_bytes());
// nothing is allocated, however many polygons are drawn.
//
//   std::vector<std::uint64_t> memory(zbuffer_workspace_bytes(512, 512) / 8 + 1);
//   ZBufferRenderer renderer;
//   check(renderer.init(memory.data(), bytes, fit_camera(box_min, box_max, {}, 512, 512)));
//   renderer.draw_polygon(positions, normals, count);  // any number of times
//   use(renderer.pixels());                            // at any time: the picture so far
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "mvox/camera.h"
#include "mvox/slice.h"
#include "mvox/status.h"

namespace mvox {

// Phong lighting with one headlight (a directional light from the viewer), per pixel:
// shade = ambient + diffuse * c + specular * c^shininess, c = |normal . towards viewer|,
// clamped to 1 and scaled to 0..255. Two-sided, so open meshes are lit from both sides.
// The defaults add up to 1: a surface facing the viewer is white, never clipped.
struct Lighting {
  float ambient = 0.10f;
  float diffuse = 0.70f;
  float specular = 0.20f;
  float shininess = 20.0f;
  std::uint8_t background = 0;
  // Skip triangles facing away from the viewer. Exact for closed, consistently wound surfaces
  // (every surface mvox extracts), and it halves the work; turn off for arbitrary meshes.
  bool cull_back_faces = true;
  // With a cutaway (Camera::cut_depth) and culling on, the surface is taken as closed: where the
  // first surface behind the plane faces away, the plane lies inside the solid, and the pixel
  // gets this flat shade instead (a cap over the cut, as a section drawing shows it).
  std::uint8_t cap = 150;
};

// What has been drawn since the last clear(). Every triangle of a projected polygon is counted
// once: triangles_culled + triangles_hidden + triangles_drawn.
struct RenderCounters {
  std::uint64_t polygons = 0;           // polygons given to draw or project
  std::uint64_t polygons_clipped = 0;   // not drawn: a vertex behind the camera or far outside
  std::uint64_t triangles_culled = 0;   // facing away (when culling), or of zero area on screen
  std::uint64_t triangles_hidden = 0;   // of polygons that would write no pixel: between pixel
                                        // centres, or behind what is already there
  std::uint64_t triangles_drawn = 0;    // rasterised and written
  std::uint64_t fragments_covered = 0;  // pixel centres inside a drawn triangle
  std::uint64_t fragments_written = 0;  // of those, nearer than what was there
};

// Bytes of workspace for a width x height image: a float depth and a byte of shade per pixel,
// plus a fixed 40 KiB for the fragments of the polygon being drawn. 0 when a size is 0 or over
// kMaxImageSide.
constexpr std::uint32_t kMaxImageSide = 16384;
std::size_t zbuffer_workspace_bytes(std::uint32_t width, std::uint32_t height);

class ZBufferRenderer {
 public:
  ZBufferRenderer() = default;
  ZBufferRenderer(const ZBufferRenderer&) = delete;
  ZBufferRenderer& operator=(const ZBufferRenderer&) = delete;

  // Prepares a cleared image of camera.width x camera.height pixels over `workspace` (borrowed;
  // at least zbuffer_workspace_bytes() bytes, aligned to alignof(float)).
  Status init(void* workspace, std::size_t workspace_bytes, const Camera& camera,
              const Lighting& lighting = {});

  // Every pixel to the background colour and infinitely far; counters to zero.
  void clear();

  // Draws one polygon of 3 .. 16 vertices (planar or not, convex or not) as a fan of triangles
  // from its first vertex. `positions` are in world units; `normals` (world axes, any length)
  // are interpolated across the polygon; with nullptr each triangle is shaded flat by its own
  // normal. Triangles follow the top-left fill rule, so an edge two triangles share is drawn
  // exactly once (no gaps, no double hits). Polygons with fewer than 3 or more than 16 vertices
  // are ignored.
  void draw_polygon(const glm::vec3* positions, const glm::vec3* normals, int vertex_count);

  // draw_polygon() in two steps, so that a caller can skip computing normals for polygons that
  // would not change the picture (most of them: facing away, between pixel centres, or hidden
  // behind what is already drawn). project_polygon() returns true when at least one pixel
  // would be written; then draw_projected() draws that polygon with `normals` (or flat, with
  // nullptr). The image is the same as with draw_polygon().
  bool project_polygon(const glm::vec3* positions, int vertex_count);
  void draw_projected(const glm::vec3* normals);

  // Sort-last compositing, for a picture drawn in parts (slabs of slices) by several renderers
  // with the same camera and lighting. Each part tags the pixels it writes: tag_pixels() gives
  // the renderer `tags` (borrowed, width * height entries, written only where a pixel is
  // drawn; null: no tags), set_tag() the current part's tag, its place in the drawing order of
  // one renderer drawing every part.
  void tag_pixels(std::uint32_t* tags) { tags_ = tags; }
  void set_tag(std::uint32_t tag) { tag_ = tag; }
  // Takes `other`'s pixel wherever it is nearer, or exactly as near and drawn by an earlier part
  // (a lower tag), since one renderer keeps the first of equal depths: both renderers' parts
  // composited give the picture one renderer draws from all of them in tag order, bit for bit,
  // whatever order the renderers are composited in. Both must tag; sizes must match (else
  // invalid_argument, nothing changed). Counters add up, but those that depend on what was
  // drawn before (hidden, drawn, fragments written) are not one renderer's.
  Status composite(const ZBufferRenderer& other);
  // The same with another picture's arrays of width() * height() entries (from another process),
  // without counters.
  Status composite(const float* depths, const std::uint8_t* shades, const std::uint32_t* tags);

  // The picture: width() * height() bytes, row by row from the top.
  const std::uint8_t* pixels() const { return shade_; }
  // The same as a u8 slice view, for image writers.
  SliceView picture() const {
    SliceView view;
    view.samples = shade_;
    view.width = width_;
    view.height = height_;
    view.row_stride_bytes = width_;
    view.type = SampleType::u8;
    return view;
  }
  // Depth per pixel in 0 (near) .. 1 (far); +infinity where nothing was drawn.
  const float* depths() const { return depth_; }
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }
  const RenderCounters& counters() const { return counters_; }

 private:
  struct ScreenVertex {
    std::int64_t x = 0, y = 0;  // pixels * 256, y down
    float depth = 0;            // 0 (near) .. 1 (far)
    float inverse_w = 1;        // 1 / clip w
    glm::vec3 normal{0.0f};     // view space over clip w: interpolates perspective-correctly
  };
  static constexpr int kMaxVerticesDrawn = 16;
  // A pixel of the projected polygon that passed the depth test when it was projected, with
  // its depth and barycentric weights, so that drawing it needs no second traversal.
  struct Fragment {
    std::uint32_t pixel = 0;
    float depth = 0;
    float weight_1 = 0, weight_2 = 0;         // of the triangle's vertices `vertex_1`, `vertex_2`
    std::uint8_t vertex_1 = 0, vertex_2 = 0;  // indices into projected_ (vertex 0 is the apex)
    bool cap = false;                          // of a triangle facing away: the cutaway's cap
  };
  static constexpr std::size_t kMaxFragments = 2048;  // per polygon; beyond: a second pass

 public:
  // Bytes of the fragment buffer, part of zbuffer_workspace_bytes().
  static constexpr std::size_t fragment_bytes() { return kMaxFragments * sizeof(Fragment); }

 private:
  // Rasterises triangle (0, i1, i2) of projected_. Without `write`: records the pixels nearer
  // than the depth buffer in fragments_ (as many as fit) and returns whether there was one.
  // With `write`: depth-tests, shades and writes them (the fallback for fragments_ overflow).
  template <bool write>
  bool draw_triangle(int i1, int i2);
  void shade_pixel(std::uint32_t pixel, float depth, const glm::vec3& normal);
  void cap_pixel(std::uint32_t pixel, float depth);
  // project_polygon()'s second half: would the projected polygon write a pixel?
  bool test_projected(int vertex_count);

  static constexpr int kShadeLevels = 1024;  // lighting lookup: c quantised to 1/1023
  float* depth_ = nullptr;
  std::uint8_t* shade_ = nullptr;
  std::uint32_t* tags_ = nullptr;  // tag_pixels()
  std::uint32_t tag_ = 0;
  std::uint32_t width_ = 0;
  std::uint32_t height_ = 0;
  Camera camera_;
  Lighting lighting_;
  float cut_depth_ = 0;       // fragments nearer than this are cut away (0: no cutaway)
  bool caps_ = false;         // back faces behind the cut draw caps (cutaway on a closed surface)
  std::uint8_t shade_of_cosine_[kShadeLevels] = {};
  RenderCounters counters_;
  // Orthographic cameras project by three affine maps: to subpixels and to depth 0..1.
  bool affine_ = false;
  glm::vec4 screen_x_{0.0f}, screen_y_{0.0f}, screen_depth_{0.0f};
  float subpixel_centre_x_ = 0, subpixel_centre_y_ = 0;
  // The polygon between project_polygon() and draw_projected().
  ScreenVertex projected_[kMaxVerticesDrawn];
  glm::vec3 projected_positions_[kMaxVerticesDrawn];
  int projected_count_ = 0;
  int projected_culled_ = 0;             // of its triangles
  std::uint64_t projected_covered_ = 0;  // pixel centres inside its triangles
  Fragment* fragments_ = nullptr;        // kMaxFragments, in the workspace
  std::size_t fragment_count_ = 0;
  bool fragments_overflowed_ = false;
};

// composite() on bare arrays of `pixels` entries, for pictures that arrive from elsewhere
// (another process): where (other_depth, other_tag) is lower than (depth, tag), the pixel takes
// the other's depth, shade and tag. Pixels never drawn have infinite depth and keep their own.
void composite_pixels(float* depth, std::uint8_t* shade, std::uint32_t* tag,
                      const float* other_depth, const std::uint8_t* other_shade,
                      const std::uint32_t* other_tag, std::size_t pixels);

}  // namespace mvox
