#pragma once
// The frame pictures are drawn in: the box to show, centred on 0 and scaled to a largest
// half-side of 1, computed in double before anything goes to the renderer's float.
//
// Why: the renderer works in float, and its camera multiplies world coordinates by the inverse
// of the box's size. For a box of 1e-35 (a spacing of 1e-37) that scale times the picture's
// subpixels is 1e40, past float's range, and every polygon was dropped as off-screen: a blank
// picture. For a box near 1e38 the scale is a subnormal, and corners of a box from -3e38 to
// 3e38 do not even have a float centre. Far from 0, a float box loses the detail of a small
// object. Orthographic and perspective fits are both unchanged by a shift and a uniform scale
// of the scene, so drawing in this frame gives the same picture, with well-scaled numbers
// whatever the world's.
#include <glm/vec3.hpp>

#include "write/mesh/world_transform.h"

namespace mvox {

struct PictureFrame {
  Vector3d centre = {0.0, 0.0, 0.0};
  double scale = 1.0;  // world = centre + scale * frame

  // The frame of the box [low, high] (world units, low <= high per axis). A box of no size
  // (a point) keeps scale 1.
  static PictureFrame around(const Vector3d& low, const Vector3d& high);

  // A world point in the frame (clamped to float's range, which only a point far outside the
  // box can leave).
  glm::vec3 point(const Vector3d& world) const;
  // A world length (a spacing, a displacement) in the frame.
  glm::vec3 length(const Vector3d& world) const;
};

}  // namespace mvox
