// Half-space triangle rasteriser after Capens (2004): vertices snapped to 1/256 pixel, integer
// edge functions evaluated at pixel centres, the top-left rule for pixels exactly on an edge.
// Depth and normals are interpolated with barycentric weights taken from the same edge
// functions, so coverage and interpolation agree.
#include "mvox/zbuffer_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <limits>

namespace mvox {
namespace {

constexpr int kSubpixelBits = 8;
constexpr std::int64_t kSubpixel = std::int64_t{1} << kSubpixelBits;
constexpr std::int64_t kHalfPixel = kSubpixel / 2;
// Vertices may lie this far outside the image (in pixels) and still be drawn; beyond it the
// polygon is dropped. Keeps fixed-point edge products far inside 64 bits.
constexpr float kGuardBandPixels = 32768.0f;
constexpr float kGuardBandSubpixels = kGuardBandPixels * kSubpixel;

// Pixel index of the first and last pixel centre at or after / at or before a subpixel
// coordinate. Right shifts of negative values floor on every compiler mvox supports (GCC and
// Clang define them as arithmetic shifts).
inline std::int64_t first_centre_at_or_after(std::int64_t subpixel) {
  return (subpixel - kHalfPixel + kSubpixel - 1) >> kSubpixelBits;
}
inline std::int64_t last_centre_at_or_before(std::int64_t subpixel) {
  return (subpixel - kHalfPixel) >> kSubpixelBits;
}

bool lighting_valid(const Lighting& l) {
  auto ok = [](float v) { return std::isfinite(v) && v >= 0.0f; };
  return ok(l.ambient) && ok(l.diffuse) && ok(l.specular) && ok(l.shininess);
}

// An edge function E(P) = (q - p) x (P - p) with its steps per pixel and its top-left bias:
// pixels exactly on a top or left edge belong to the triangle, on other edges they do not.
struct Edge {
  std::int64_t at_start = 0;  // at the first pixel centre of the bounding box, bias included
  std::int64_t step_x = 0;
  std::int64_t step_y = 0;
  std::int64_t bias = 0;  // 0 or -1

  Edge(std::int64_t px, std::int64_t py, std::int64_t qx, std::int64_t qy, std::int64_t start_x,
       std::int64_t start_y) {
    const std::int64_t dx = qx - px, dy = qy - py;
    // With y pointing down and triangles wound so that the area is positive, interior lies
    // to the right of each edge: a top edge runs along +x, a left edge runs up (dy < 0).
    const bool top_left = (dy == 0 && dx > 0) || dy < 0;
    bias = top_left ? 0 : -1;
    at_start = dx * (start_y - py) - dy * (start_x - px) + bias;
    step_x = -dy * kSubpixel;
    step_y = dx * kSubpixel;
  }
};

}  // namespace

std::size_t zbuffer_workspace_bytes(std::uint32_t width, std::uint32_t height) {
  if (width == 0 || height == 0 || width > kMaxImageSide || height > kMaxImageSide) return 0;
  return std::size_t{width} * height * (sizeof(float) + sizeof(std::uint8_t)) +
         ZBufferRenderer::fragment_bytes();
}

Status ZBufferRenderer::init(void* workspace, std::size_t workspace_bytes, const Camera& camera,
                             const Lighting& lighting) {
  depth_ = nullptr;
  shade_ = nullptr;
  const std::size_t needed = zbuffer_workspace_bytes(camera.width, camera.height);
  if (!workspace || needed == 0 || !lighting_valid(lighting)) return Status::invalid_argument;
  if (reinterpret_cast<std::uintptr_t>(workspace) % alignof(float) != 0)
    return Status::workspace_misaligned;
  if (workspace_bytes < needed) return Status::workspace_too_small;
  width_ = camera.width;
  height_ = camera.height;
  camera_ = camera;
  lighting_ = lighting;
  cut_depth_ = camera.cut_depth > 0.0f ? camera.cut_depth : 0.0f;  // NaN: no cut
  caps_ = cut_depth_ > 0.0f && lighting.cull_back_faces;
  depth_ = static_cast<float*>(workspace);
  // Floats first, then the fragments (4-byte aligned after them), then the bytes of shade.
  fragments_ = reinterpret_cast<Fragment*>(depth_ + std::size_t{width_} * height_);
  shade_ = reinterpret_cast<std::uint8_t*>(fragments_ + kMaxFragments);
  // An orthographic camera's clip w is 1 everywhere: then the whole projection to subpixels
  // and depth is one affine map per coordinate.
  const glm::mat4& m = camera.world_to_clip;  // m[column][row]
  affine_ = m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f;
  const float sub_half_width = 0.5f * static_cast<float>(width_) * kSubpixel;
  const float sub_half_height = 0.5f * static_cast<float>(height_) * kSubpixel;
  for (int column = 0; column < 4; ++column) {
    screen_x_[column] = sub_half_width * m[column][0];
    screen_y_[column] = -sub_half_height * m[column][1];
    screen_depth_[column] = 0.5f * m[column][2];
  }
  screen_x_.w += sub_half_width;
  screen_y_.w += sub_half_height;
  screen_depth_.w += 0.5f;
  subpixel_centre_x_ = sub_half_width;
  subpixel_centre_y_ = sub_half_height;
  // The whole lighting model folded into a table of the cosine: no pow() per pixel.
  for (int i = 0; i < kShadeLevels; ++i) {
    const float c = static_cast<float>(i) / (kShadeLevels - 1);
    float shade = lighting.ambient + lighting.diffuse * c +
                  lighting.specular * std::pow(c, lighting.shininess);
    shade = shade < 0.0f ? 0.0f : shade > 1.0f ? 1.0f : shade;
    shade_of_cosine_[i] = static_cast<std::uint8_t>(std::lround(shade * 255.0f));
  }
  clear();
  return Status::ok;
}

void ZBufferRenderer::clear() {
  const std::size_t pixels = std::size_t{width_} * height_;
  for (std::size_t i = 0; i < pixels; ++i) depth_[i] = std::numeric_limits<float>::infinity();
  std::memset(shade_, lighting_.background, pixels);
  counters_ = RenderCounters();
}

void composite_pixels(float* depth, std::uint8_t* shade, std::uint32_t* tag,
                      const float* other_depth, const std::uint8_t* other_shade,
                      const std::uint32_t* other_tag, std::size_t pixels) {
  for (std::size_t i = 0; i < pixels; ++i) {
    const float d = other_depth[i];
    // Infinite depths are never taken: a pixel drawn nowhere keeps the background.
    const bool takes = d < depth[i] || (d == depth[i] && other_tag[i] < tag[i] &&
                                        d != std::numeric_limits<float>::infinity());
    if (!takes) continue;
    depth[i] = d;
    shade[i] = other_shade[i];
    tag[i] = other_tag[i];
  }
}

Status ZBufferRenderer::composite(const ZBufferRenderer& other) {
  if (!depth_ || !other.depth_ || !tags_ || !other.tags_ || other.width_ != width_ ||
      other.height_ != height_)
    return Status::invalid_argument;
  composite_pixels(depth_, shade_, tags_, other.depth_, other.shade_, other.tags_,
                   std::size_t{width_} * height_);
  counters_.polygons += other.counters_.polygons;
  counters_.polygons_clipped += other.counters_.polygons_clipped;
  counters_.triangles_culled += other.counters_.triangles_culled;
  counters_.triangles_hidden += other.counters_.triangles_hidden;
  counters_.triangles_drawn += other.counters_.triangles_drawn;
  counters_.fragments_covered += other.counters_.fragments_covered;
  counters_.fragments_written += other.counters_.fragments_written;
  return Status::ok;
}

Status ZBufferRenderer::composite(const float* depths, const std::uint8_t* shades,
                                  const std::uint32_t* tags) {
  if (!depth_ || !tags_ || !depths || !shades || !tags) return Status::invalid_argument;
  composite_pixels(depth_, shade_, tags_, depths, shades, tags, std::size_t{width_} * height_);
  return Status::ok;
}

void ZBufferRenderer::draw_polygon(const glm::vec3* positions, const glm::vec3* normals,
                                   int vertex_count) {
  if (project_polygon(positions, vertex_count)) draw_projected(normals);
}

bool ZBufferRenderer::project_polygon(const glm::vec3* positions, int vertex_count) {
  projected_count_ = 0;
  if (!depth_ || vertex_count < 3 || vertex_count > kMaxVerticesDrawn) return false;
  ++counters_.polygons;
  if (affine_) {
    // Orthographic: screen coordinates are affine in the position, no division.
    for (int i = 0; i < vertex_count; ++i) {
      const glm::vec3& p = positions[i];
      const float sx = screen_x_.x * p.x + screen_x_.y * p.y + screen_x_.z * p.z + screen_x_.w;
      const float sy = screen_y_.x * p.x + screen_y_.y * p.y + screen_y_.z * p.z + screen_y_.w;
      if (!(std::fabs(sx - subpixel_centre_x_) < kGuardBandSubpixels &&
            std::fabs(sy - subpixel_centre_y_) < kGuardBandSubpixels)) {
        ++counters_.polygons_clipped;
        return false;
      }
      ScreenVertex& v = projected_[i];
      v.x = std::lrint(sx);  // nearest subpixel; the guard band keeps it in range
      v.y = std::lrint(sy);
      v.depth =
          screen_depth_.x * p.x + screen_depth_.y * p.y + screen_depth_.z * p.z + screen_depth_.w;
      v.inverse_w = 1.0f;
      projected_positions_[i] = p;
    }
    return test_projected(vertex_count);
  }
  const glm::mat4& to_clip = camera_.world_to_clip;
  const float half_width = 0.5f * static_cast<float>(width_);
  const float half_height = 0.5f * static_cast<float>(height_);
  for (int i = 0; i < vertex_count; ++i) {
    const glm::vec4 clip = to_clip * glm::vec4(positions[i], 1.0f);
    if (!(clip.w > 1e-20f)) {  // behind the eye (perspective), or NaN
      ++counters_.polygons_clipped;
      return false;
    }
    ScreenVertex& v = projected_[i];
    v.inverse_w = 1.0f / clip.w;
    const float sx = (clip.x * v.inverse_w + 1.0f) * half_width;
    const float sy = (1.0f - clip.y * v.inverse_w) * half_height;
    if (!(std::fabs(sx - half_width) < kGuardBandPixels &&
          std::fabs(sy - half_height) < kGuardBandPixels)) {
      ++counters_.polygons_clipped;
      return false;
    }
    // Round to the subpixel grid (the guard band keeps this far inside int64).
    v.x = std::lrint(sx * kSubpixel);
    v.y = std::lrint(sy * kSubpixel);
    v.depth = 0.5f * (clip.z * v.inverse_w + 1.0f);
    projected_positions_[i] = positions[i];
  }
  return test_projected(vertex_count);
}

bool ZBufferRenderer::test_projected(int vertex_count) {
  projected_count_ = vertex_count;
  projected_culled_ = 0;
  projected_covered_ = 0;
  fragment_count_ = 0;
  fragments_overflowed_ = false;
  // Would any pixel be written? Every triangle is rasterised once here, without writing, and
  // the pixels nearer than the depth buffer are kept for draw_projected().
  bool visible = false;
  for (int i = 1; i + 1 < vertex_count; ++i) visible = draw_triangle<false>(i, i + 1) || visible;
  const int triangles = vertex_count - 2;
  counters_.triangles_culled += static_cast<std::uint64_t>(projected_culled_);
  if (!visible) {
    counters_.triangles_hidden += static_cast<std::uint64_t>(triangles - projected_culled_);
    projected_count_ = 0;
  }
  return visible;
}

void ZBufferRenderer::shade_pixel(std::uint32_t pixel, float depth, const glm::vec3& normal) {
  ++counters_.fragments_written;
  depth_[pixel] = depth;
  if (tags_) tags_[pixel] = tag_;
  const float length_squared = glm::dot(normal, normal);
  // min(): rounding can put the quotient a hair above 1, past the table's end.
  const float cosine = length_squared > 0.0f
                           ? std::min(1.0f, std::fabs(normal.z) / std::sqrt(length_squared))
                           : 0.0f;
  shade_[pixel] = shade_of_cosine_[static_cast<int>(cosine * (kShadeLevels - 1) + 0.5f)];
}

void ZBufferRenderer::cap_pixel(std::uint32_t pixel, float depth) {
  ++counters_.fragments_written;
  depth_[pixel] = depth;
  if (tags_) tags_[pixel] = tag_;
  shade_[pixel] = lighting_.cap;
}

void ZBufferRenderer::draw_projected(const glm::vec3* normals) {
  const int count = projected_count_;
  projected_count_ = 0;
  if (count < 3) return;
  counters_.triangles_drawn += static_cast<std::uint64_t>(count - 2 - projected_culled_);
  counters_.fragments_covered += projected_covered_;
  if (normals) {
    for (int i = 0; i < count; ++i)
      projected_[i].normal = camera_.world_to_view * normals[i] * projected_[i].inverse_w;
    if (!fragments_overflowed_) {
      // The kept pixels, in the order a second traversal would visit them; a pixel can
      // appear twice when a non-planar polygon folds over itself, so test depth again.
      const glm::vec3& normal_0 = projected_[0].normal;
      for (std::size_t f = 0; f < fragment_count_; ++f) {
        const Fragment& fragment = fragments_[f];
        if (!(fragment.depth < depth_[fragment.pixel])) continue;
        if (fragment.cap) {
          cap_pixel(fragment.pixel, fragment.depth);
          continue;
        }
        const glm::vec3 n = normal_0 +
                            fragment.weight_1 * (projected_[fragment.vertex_1].normal - normal_0) +
                            fragment.weight_2 * (projected_[fragment.vertex_2].normal - normal_0);
        shade_pixel(fragment.pixel, fragment.depth, n);
      }
      return;
    }
    for (int i = 1; i + 1 < count; ++i) draw_triangle<true>(i, i + 1);
    return;
  }
  const glm::vec3* p = projected_positions_;
  for (int i = 1; i + 1 < count; ++i) {
    // Flat: the triangle's own normal at its three corners (set just before it is drawn).
    const glm::vec3 n = camera_.world_to_view * glm::cross(p[i] - p[0], p[i + 1] - p[0]);
    projected_[0].normal = projected_[i].normal = projected_[i + 1].normal = n;
    draw_triangle<true>(i, i + 1);
  }
}

template <bool write>
bool ZBufferRenderer::draw_triangle(int i1, int i2) {
  const ScreenVertex* v0 = &projected_[0];
  const ScreenVertex* v1 = &projected_[i1];
  const ScreenVertex* v2 = &projected_[i2];
  // Twice the signed area in y-down pixel coordinates. A triangle wound counter-clockwise as
  // seen (y up: it faces the viewer) turns clockwise when y points down, which makes this
  // negative. Edge functions below want it positive: front faces are drawn as (v0, v2, v1).
  std::int64_t area = (v1->x - v0->x) * (v2->y - v0->y) - (v1->y - v0->y) * (v2->x - v0->x);
  // Facing away on a closed surface under a cutaway: drawn, as the cap over the cut.
  const bool cap = area > 0 && caps_;
  if (area >= 0) {  // facing away, or edge-on
    if (area == 0 || (lighting_.cull_back_faces && !cap)) {
      if constexpr (!write) ++projected_culled_;  // counted once, when projected
      return false;
    }
  } else {
    const ScreenVertex* swap = v1;
    v1 = v2;
    v2 = swap;
    const int swap_index = i1;
    i1 = i2;
    i2 = swap_index;
    area = -area;
  }

  // Pixels whose centre (px + 1/2, py + 1/2) lies in the bounding box, clipped to the image.
  const std::int64_t min_x = std::min({v0->x, v1->x, v2->x});
  const std::int64_t max_x = std::max({v0->x, v1->x, v2->x});
  const std::int64_t min_y = std::min({v0->y, v1->y, v2->y});
  const std::int64_t max_y = std::max({v0->y, v1->y, v2->y});
  const std::int64_t first_x = std::max<std::int64_t>(0, first_centre_at_or_after(min_x));
  const std::int64_t last_x = std::min<std::int64_t>(width_ - 1, last_centre_at_or_before(max_x));
  const std::int64_t first_y = std::max<std::int64_t>(0, first_centre_at_or_after(min_y));
  const std::int64_t last_y = std::min<std::int64_t>(height_ - 1, last_centre_at_or_before(max_y));
  if (first_x > last_x || first_y > last_y) return false;

  const std::int64_t start_x = first_x * kSubpixel + kHalfPixel;
  const std::int64_t start_y = first_y * kSubpixel + kHalfPixel;
  // Edge i is opposite vertex i; its value over the area is vertex i's barycentric weight.
  const Edge e0(v1->x, v1->y, v2->x, v2->y, start_x, start_y);
  const Edge e1(v2->x, v2->y, v0->x, v0->y, start_x, start_y);
  const Edge e2(v0->x, v0->y, v1->x, v1->y, start_x, start_y);

  const float inverse_area = 1.0f / static_cast<float>(area);
  const float depth_1 = v1->depth - v0->depth, depth_2 = v2->depth - v0->depth;
  // Normals are only needed when writing; the test pass skips them (if constexpr below).
  const glm::vec3 normal_1 = write ? v1->normal - v0->normal : glm::vec3(0.0f);
  const glm::vec3 normal_2 = write ? v2->normal - v0->normal : glm::vec3(0.0f);

  bool any_nearer = false;
  std::int64_t row_w0 = e0.at_start, row_w1 = e1.at_start, row_w2 = e2.at_start;
  for (std::int64_t py = first_y; py <= last_y; ++py) {
    std::int64_t w0 = row_w0, w1 = row_w1, w2 = row_w2;
    const std::size_t row_start = static_cast<std::size_t>(py) * width_;
    for (std::int64_t px = first_x; px <= last_x; ++px) {
      if ((w0 | w1 | w2) >= 0) {
        const float l1 = static_cast<float>(w1 - e1.bias) * inverse_area;
        const float l2 = static_cast<float>(w2 - e2.bias) * inverse_area;
        const float depth = v0->depth + l1 * depth_1 + l2 * depth_2;
        const auto pixel = static_cast<std::uint32_t>(row_start + static_cast<std::size_t>(px));
        const bool nearer =
            depth < depth_[pixel] && depth >= cut_depth_ && depth >= 0.0f && depth <= 1.0f;
        if constexpr (!write) {
          ++projected_covered_;
          if (nearer) {
            any_nearer = true;
            if (fragment_count_ < kMaxFragments)
              fragments_[fragment_count_++] = {pixel,
                                               depth,
                                               l1,
                                               l2,
                                               static_cast<std::uint8_t>(i1),
                                               static_cast<std::uint8_t>(i2),
                                               cap};
            else
              fragments_overflowed_ = true;
          }
        } else if (nearer) {
          any_nearer = true;
          if (cap)
            cap_pixel(pixel, depth);
          else
            shade_pixel(pixel, depth, v0->normal + l1 * normal_1 + l2 * normal_2);
        }
      }
      w0 += e0.step_x;
      w1 += e1.step_x;
      w2 += e2.step_x;
    }
    row_w0 += e0.step_y;
    row_w1 += e1.step_y;
    row_w2 += e2.step_y;
  }
  return any_nearer;
}

}  // namespace mvox
