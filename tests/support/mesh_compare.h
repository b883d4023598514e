#pragma once
// Test support: exact equality of two engine outputs (same vertices in the same order, same
// polygons with the same vertex order), with a message that says where they first differ.
#include <gtest/gtest.h>

#include "mesh_capture.h"

namespace mvox::test {

inline ::testing::AssertionResult meshes_identical(const Mesh& a, const Mesh& b) {
  if (a.vertices.size() != b.vertices.size())
    return ::testing::AssertionFailure()
           << "vertex counts differ: " << a.vertices.size() << " vs " << b.vertices.size();
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    const Vertex &u = a.vertices[i], &v = b.vertices[i];
    if (!same_position(u, v) || u.axis != v.axis || u.inner_is_lower != v.inner_is_lower)
      return ::testing::AssertionFailure()
             << "vertex " << i << " differs: (" << u.x << "," << u.y << "," << u.z << ") vs ("
             << v.x << "," << v.y << "," << v.z << ")";
  }
  if (a.polygons.size() != b.polygons.size())
    return ::testing::AssertionFailure()
           << "polygon counts differ: " << a.polygons.size() << " vs " << b.polygons.size();
  for (std::size_t i = 0; i < a.polygons.size(); ++i)
    if (a.polygons[i] != b.polygons[i])
      return ::testing::AssertionFailure() << "polygon " << i << " differs";
  return ::testing::AssertionSuccess();
}

}  // namespace mvox::test
