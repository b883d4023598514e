#include "mvox/vertex_normals.h"

#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>

#include "sample_load.h"

namespace mvox {
namespace {

// Samples of a window with coordinates clamped to the volume seen so far (slice_window.h).
template <SampleType kType>
class ClampedSamples {
 public:
  explicit ClampedSamples(const SliceWindow& window)
      : window_(window),
        last_x_(std::int64_t{window.width()} - 1),
        last_y_(std::int64_t{window.height()} - 1),
        last_z_(std::int64_t{window.slices()} - 1) {}

  float operator()(std::int64_t x, std::int64_t y, std::int64_t z) const {
    x = x < 0 ? 0 : x > last_x_ ? last_x_ : x;
    y = y < 0 ? 0 : y > last_y_ ? last_y_ : y;
    z = z < 0 ? 0 : z > last_z_ ? last_z_ : z;
    return load_sample<kType>(
        window_.row(static_cast<std::uint32_t>(y), static_cast<std::uint32_t>(z)),
        static_cast<std::uint32_t>(x));
  }

  // Central differences at voxel (x, y, z), not yet divided by twice the spacing.
  glm::vec3 differences(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const ClampedSamples& d = *this;
    return {d(x + 1, y, z) - d(x - 1, y, z), d(x, y + 1, z) - d(x, y - 1, z),
            d(x, y, z + 1) - d(x, y, z - 1)};
  }

  std::int64_t extent(int axis) const {
    return (axis == 0 ? last_x_ : axis == 1 ? last_y_ : last_z_) + 1;
  }

 private:
  const SliceWindow& window_;
  std::int64_t last_x_, last_y_, last_z_;
};

// Central differences at voxels a and a + e_axis, weighted by wa and wb and summed, for a pair
// well inside the volume: every neighbour exists, so rows are addressed directly, without
// clamping.
template <SampleType kType>
glm::vec3 interior_differences(const SliceWindow& window, const std::int64_t a[3], int axis,
                               float wa, float wb) {
  const auto x = static_cast<std::uint32_t>(a[0]), y = static_cast<std::uint32_t>(a[1]);
  const auto z = static_cast<std::uint32_t>(a[2]);
  // d(dx, dy, dz) relative to a, with dx, dy, dz in -1 .. 2 (2 only along `axis`). Grouped as
  // ClampedSamples::differences() sums, so both paths round alike.
  // always_inline: twelve calls with constant offsets fold into plain loads.
  auto d = [&](int dx, int dy, int dz) __attribute__((always_inline)) {
    return load_sample<kType>(window.row(y + dy, z + dz), x + dx);
  };
  const int bx = axis == 0, by = axis == 1, bz = axis == 2;  // b = a + (bx, by, bz)
  return {wa * (d(1, 0, 0) - d(-1, 0, 0)) + wb * (d(bx + 1, by, bz) - d(bx - 1, by, bz)),
          wa * (d(0, 1, 0) - d(0, -1, 0)) + wb * (d(bx, by + 1, bz) - d(bx, by - 1, bz)),
          wa * (d(0, 0, 1) - d(0, 0, -1)) + wb * (d(bx, by, bz + 1) - d(bx, by, bz - 1))};
}

template <SampleType kType>
glm::vec3 normal_at(const ClampedSamples<kType>& samples, const SliceWindow& window,
                    const glm::vec3& inverse_double_spacing, const Vertex& v) {
  const int axis = static_cast<int>(v.axis);
  glm::vec3 outward_axis(0.0f);
  outward_axis[axis] = v.inner_is_lower ? 1.0f : -1.0f;
  // The voxel pair: a is the lower along `axis`, b = a + 1. Across the axis the coordinates are
  // whole voxel indices (>= 0), so a cast is exact. Along it the vertex sits at a + t: t = 1/2
  // for marching voxels, the interpolated crossing for marching cubes. A crossing exactly at a
  // voxel (t = 0 or 1) lies at the inner voxel, so the pair is the one on its outer side.
  std::int64_t a[3] = {static_cast<std::int64_t>(v.x), static_cast<std::int64_t>(v.y),
                       static_cast<std::int64_t>(v.z)};
  const float along = axis == 0 ? v.x : axis == 1 ? v.y : v.z;
  const float lower = v.inner_is_lower ? std::floor(along) : -std::floor(-along) - 1.0f;
  a[axis] = static_cast<std::int64_t>(lower);
  // The gradient interpolated linearly between the pair, as Lorensen and Cline do, scaled by 2
  // so that a midpoint's weights are exactly 1 and 1.
  float t = along - lower;
  t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
  const float wa = 2.0f * (1.0f - t), wb = 2.0f * t;
  if (a[axis] < 0 || a[axis] + 1 >= samples.extent(axis)) return outward_axis;
  glm::vec3 differences;
  // Both voxels' neighbours inside the volume: the common case, read without clamping.
  bool interior = true;
  for (int k = 0; k < 3; ++k)
    interior = interior && a[k] >= 1 && a[k] + (k == axis ? 2 : 1) < samples.extent(k);
  if (interior) {
    differences = interior_differences<kType>(window, a, axis, wa, wb);
  } else {
    std::int64_t b[3] = {a[0], a[1], a[2]};
    ++b[axis];
    differences =
        wa * samples.differences(a[0], a[1], a[2]) + wb * samples.differences(b[0], b[1], b[2]);
  }
  const glm::vec3 gradient = differences * inverse_double_spacing;
  const float length_squared = glm::dot(gradient, gradient);
  if (!(length_squared > 0.0f) || !std::isfinite(length_squared)) return outward_axis;
  return gradient * (-1.0f / std::sqrt(length_squared));
}

}  // namespace

VertexNormals::VertexNormals(const SliceWindow& window, const glm::vec3& spacing)
    : window_(window), inverse_double_spacing_(0.5f / spacing) {}

glm::vec3 VertexNormals::operator()(const Vertex& vertex) const {
  glm::vec3 normal;
  compute(&vertex, 1, &normal);
  return normal;
}

void VertexNormals::compute(const Vertex* vertices, std::size_t vertex_count,
                            glm::vec3* normals) const {
  dispatch_sample_type(window_.type(), [&](auto tag) {
    constexpr SampleType kType = decltype(tag)::value;
    const ClampedSamples<kType> samples(window_);
    for (std::size_t i = 0; i < vertex_count; ++i)
      normals[i] = normal_at(samples, window_, inverse_double_spacing_, vertices[i]);
  });
}

}  // namespace mvox
