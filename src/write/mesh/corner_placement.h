#pragma once
// Where the corners of STL's triangles land: WorldTransform::position() of each, rounded to
// float, a polygon's corners at a time (stl_triangle_records.h), before its triangles share them.
#include "mvox/mesh.h"
#include "write/mesh/world_transform.h"

namespace mvox {

// Immutable once made: any number of threads may place with one.
class CornerPlacement {
 public:
  // `transform` must pass its check().
  explicit CornerPlacement(const WorldTransform& transform);

  // position() of each of `count` vertices, rounded to float, into out[i] as x, y, z, 0: the
  // very floats position() gives, in rows of 16 bytes that are stored whole (STL's records take
  // them so, stl_triangle_records.h). False when a coordinate leaves float's range (out is then
  // not to be used): the caller names the vertex the careful way.
  bool place(const Vertex* vertices, int count, float (*out)[4]) const;

 private:
  WorldTransform transform_;
  // position() is origin + spacing * v per axis, bit for bit: identity axes, and no origin
  // coordinate -0 (position() adds the other axes' zero terms, and -0 + +0 is +0).
  bool plain_sum_;
  // And spacing 1, origin +0 (a raw volume's default): +0 + 1 * v is v itself, in float, but
  // for -0, which becomes +0 as adding +0.0f makes it.
  bool identity_;
};

}  // namespace mvox
