#include "write/mesh/axis_aligned_placement.h"

#include <cmath>

namespace mvox {

bool is_identity_placement(const WorldTransform& transform) {
  for (int axis = 0; axis < 3; ++axis)
    if (transform.spacing[axis] != 1.0 || transform.origin[axis] != 0.0 ||
        std::signbit(transform.origin[axis]))
      return false;
  return true;
}

}  // namespace mvox
