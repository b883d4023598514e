#include "picture/picture_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mvox {

PictureFrame PictureFrame::around(const Vector3d& low, const Vector3d& high) {
  PictureFrame frame;
  double half_side = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    // Halves first: low + high, or high - low, of two values near double's largest overflows.
    frame.centre[axis] = 0.5 * low[axis] + 0.5 * high[axis];
    half_side = std::max(half_side, 0.5 * high[axis] - 0.5 * low[axis]);
  }
  if (half_side > 0.0 && std::isfinite(half_side)) frame.scale = half_side;
  return frame;
}

namespace {

// `value` as a float, clamped to float's range: a point far outside the box (a vertex no face
// uses) may lie past it in the frame, and converting it unclamped would be undefined behaviour.
float clamped(double value) {
  constexpr double kLargest = std::numeric_limits<float>::max();
  return static_cast<float>(std::clamp(value, -kLargest, kLargest));
}

}  // namespace

glm::vec3 PictureFrame::point(const Vector3d& world) const {
  return glm::vec3(clamped((world[0] - centre[0]) / scale), clamped((world[1] - centre[1]) / scale),
                   clamped((world[2] - centre[2]) / scale));
}

glm::vec3 PictureFrame::length(const Vector3d& world) const {
  return glm::vec3(clamped(world[0] / scale), clamped(world[1] / scale), clamped(world[2] / scale));
}

}  // namespace mvox
