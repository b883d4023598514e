// STL's triangle records made straight from the engine's polygons (stl_triangle_records.h),
// against the same records built the plain way from their definition: the fan from the first
// corner whose diagonals avoid the cube faces (found with floor(), apart from fan_apex()),
// walked backwards under a mirroring placement, WorldTransform::position() rounded to
// float, stl_face_normal() one triangle at a time, little-endian stores and a zero attribute.
// Also the pairs of normals against the single formula.
#include "write/mesh/stl_triangle_records.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "write/mesh/little_endian.h"
#include "write/mesh/world_transform.h"

namespace mvox {
namespace {

// Polygons of 3 to 7 corners whose coordinates are whole or half numbers, so that corners often
// share cube faces: many polygons are fanned from a corner other than the first, and some from
// none (make_stl_triangle_records stops there).
PolygonGeometry random_polygon(std::mt19937& random) {
  PolygonGeometry polygon;
  polygon.vertex_count = static_cast<std::uint8_t>(3 + random() % 5);
  for (int k = 0; k < polygon.vertex_count; ++k) {
    float* xyz[3] = {&polygon.vertices[k].x, &polygon.vertices[k].y, &polygon.vertices[k].z};
    for (float* coordinate : xyz)
      *coordinate = static_cast<float>(random() % 6) + (random() % 2 ? 0.5f : 0.0f) - 2.0f;
  }
  return polygon;
}

// The fan's apex by the definition, with floor(), apart from fan_apex(): the first corner none
// of whose diagonals joins it to a corner on a common cube face (a shared whole coordinate); -1
// when there is none.
int first_apex(const PolygonGeometry& polygon) {
  const int n = polygon.vertex_count;
  for (int apex = 0; apex < n; ++apex) {
    bool fits = true;
    for (int step = 2; step <= n - 2; ++step) {
      const Vertex& a = polygon.vertices[apex];
      const Vertex& b = polygon.vertices[(apex + step) % n];
      const float pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z};
      for (int axis = 0; axis < 3; ++axis)
        if (pa[axis] == pb[axis] && std::floor(pa[axis]) == pa[axis]) fits = false;
    }
    if (fits) return apex;
  }
  return -1;
}

// The records of `polygons`, the plain way; false when one cannot be split.
bool plain_records(const WorldTransform& transform, const std::vector<PolygonGeometry>& polygons,
                   std::vector<unsigned char>* records) {
  const bool mirrors = transform.mirrors();
  for (const PolygonGeometry& polygon : polygons) {
    const int n = polygon.vertex_count;
    const int apex = first_apex(polygon);
    if (apex < 0) return false;
    for (int i = 1; i <= n - 2; ++i) {
      const int c[3] = {apex, (apex + i) % n, (apex + i + 1) % n};
      const int order[3] = {c[0], mirrors ? c[2] : c[1], mirrors ? c[1] : c[2]};
      float p[3][3];
      for (int k = 0; k < 3; ++k) {
        const Vertex& v = polygon.vertices[order[k]];
        const Vector3d world = transform.position(v.x, v.y, v.z);
        for (int axis = 0; axis < 3; ++axis) p[k][axis] = static_cast<float>(world[axis]);
      }
      float normal[3];
      stl_face_normal(p, normal);
      unsigned char record[kStlTriangleBytes];
      unsigned char* out = record;
      for (float value : normal) out = store_le_float(out, value);
      for (auto& corner : p)
        for (float value : corner) out = store_le_float(out, value);
      out[0] = out[1] = 0;
      records->insert(records->end(), record, record + sizeof record);
    }
  }
  return true;
}

std::vector<WorldTransform> placements() {
  std::vector<WorldTransform> transforms(4);
  transforms[1].spacing = {0.3, 0.7, 2.5};  // a scan's spacing, no origin
  transforms[1].origin = {-120.25, 0.0, 33.5};
  transforms[2].axes = {{{0, -1, 0}, {-1, 0, 0}, {0, 0.1, 1}}};  // mirrored, sheared
  transforms[2].origin = {10.25, -20, 3.5};
  transforms[3].axes = {{{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};  // x flipped: mirrored
  transforms[3].spacing = {0.5, 0.5, 1.25};
  for (const WorldTransform& transform : transforms) transform.check("test");
  return transforms;
}

// Runs of 0 to 300 polygons that can all be split, on the raw default, a scan's spacing and two
// mirroring placements: byte for byte the plain records, and not a byte written past the
// records and the slack.
TEST(StlTriangleRecords, AreThePlainRecordsOfEveryPolygonOnAnyPlacement) {
  std::mt19937 random(20261127);
  int fanned_elsewhere = 0;
  for (const WorldTransform& transform : placements()) {
    const CornerPlacement placement(transform);
    for (std::size_t count : {0, 1, 2, 3, 7, 64, 300}) {
      std::vector<PolygonGeometry> polygons;
      while (polygons.size() < count) {
        const PolygonGeometry polygon = random_polygon(random);
        const int apex = first_apex(polygon);
        if (apex < 0) continue;
        fanned_elsewhere += apex > 0;
        polygons.push_back(polygon);
      }
      std::vector<unsigned char> expected;
      ASSERT_TRUE(plain_records(transform, polygons, &expected));
      constexpr unsigned char kGuard = 0xA5;
      const std::size_t room = count * kMostStlBytesPerPolygon + kStlRecordSlack;
      std::vector<unsigned char> out(room + 64, kGuard);
      const StlRecordsMade made = make_stl_triangle_records(placement, transform.mirrors(),
                                                            polygons.data(), count, out.data());
      EXPECT_EQ(made.polygons, count);
      ASSERT_EQ(made.triangles * kStlTriangleBytes, expected.size());
      ASSERT_EQ(std::memcmp(out.data(), expected.data(), expected.size()), 0)
          << count << " polygons, mirrored " << transform.mirrors();
      for (std::size_t i = room; i < out.size(); ++i)
        ASSERT_EQ(out[i], kGuard) << "byte " << i << " past the room of " << count << " polygons";
    }
  }
  EXPECT_GT(fanned_elsewhere, 100) << "the polygons hardly tried the fan's other apexes";
}

// Runs of heptagons only, each split into five triangles, fill the room to its last byte: the
// records and the slack, and not a byte past them.
TEST(StlTriangleRecords, HeptagonsFillTheRoomToItsLastByteAndNoFurther) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(0.1f, 0.9f);  // never whole: apex 0 fits
  const CornerPlacement placement{WorldTransform()};
  for (std::size_t count : {1, 2, 129}) {
    std::vector<PolygonGeometry> polygons(count);
    for (PolygonGeometry& polygon : polygons) {
      polygon.vertex_count = kMaxPolygonVertices;
      for (int k = 0; k < kMaxPolygonVertices; ++k)
        polygon.vertices[k] = {coordinate(random) + k, coordinate(random), coordinate(random)};
    }
    constexpr unsigned char kGuard = 0x5A;
    const std::size_t room = count * kMostStlBytesPerPolygon + kStlRecordSlack;
    std::vector<unsigned char> out(room + 32, kGuard);
    const StlRecordsMade made =
        make_stl_triangle_records(placement, false, polygons.data(), count, out.data());
    ASSERT_EQ(made.triangles, count * (kMaxPolygonVertices - 2));
    std::vector<unsigned char> expected;
    ASSERT_TRUE(plain_records(WorldTransform(), polygons, &expected));
    ASSERT_EQ(std::memcmp(out.data(), expected.data(), expected.size()), 0);
    for (std::size_t i = room; i < out.size(); ++i)
      ASSERT_EQ(out[i], kGuard) << "byte " << i << " past the room of " << count << " heptagons";
  }
}

// A polygon it cannot make stops the run before it, with the ones before it made: a corner
// beyond float's range once placed, a square lying in a cube face, a polygon of 8 corners.
TEST(StlTriangleRecords, StopBeforeAPolygonTheyCannotMake) {
  WorldTransform far;
  far.spacing = {1.0, 1.0, 1e36};  // z beyond 340 leaves float's range
  far.check("test");
  const CornerPlacement placement(far);
  std::vector<PolygonGeometry> polygons(3);
  for (PolygonGeometry& polygon : polygons) {
    polygon.vertex_count = 3;
    polygon.vertices[1].x = 1;
    polygon.vertices[2].y = 1;
  }
  PolygonGeometry square;
  square.vertex_count = 4;
  const float corners[4][2] = {{0.5f, 0}, {1, 0.5f}, {0.5f, 1}, {0, 0.5f}};
  for (int k = 0; k < 4; ++k) square.vertices[k] = {corners[k][0], corners[k][1], 0.0f};
  PolygonGeometry octagon = polygons[0];
  octagon.vertex_count = 8;
  PolygonGeometry beyond = polygons[0];
  beyond.vertices[2].z = 400;
  for (const PolygonGeometry& bad : {beyond, square, octagon}) {
    std::vector<PolygonGeometry> run = polygons;
    run[2] = bad;
    std::vector<unsigned char> out(3 * kMostStlBytesPerPolygon + kStlRecordSlack);
    const StlRecordsMade made =
        make_stl_triangle_records(placement, false, run.data(), run.size(), out.data());
    EXPECT_EQ(made.polygons, 2u);
    EXPECT_EQ(made.triangles, 2u);
    std::vector<unsigned char> expected;
    ASSERT_TRUE(plain_records(far, {run[0], run[1]}, &expected));
    EXPECT_EQ(std::memcmp(out.data(), expected.data(), expected.size()), 0);
  }
}

#if defined(__SSE2__)
// STL's face normals two triangles at a time: the floats of the one-at-a-time formula, for
// ordinary, needle-thin and degenerate (no area: normal 0) triangles.
TEST(StlFaceNormals, APairGivesEachTriangleTheNormalItGetsAlone) {
  std::mt19937 random(5);
  std::uniform_real_distribution<float> coordinate(-300.0f, 300.0f);
  for (int round = 0; round < 20000; ++round) {
    float p[3][3], q[3][3];
    for (auto* triangle : {p, q})
      for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis) triangle[k][axis] = coordinate(random);
    if (round % 4 == 1) std::memcpy(q[2], q[1], sizeof q[1]);     // two corners alike: no area
    if (round % 4 == 2) p[2][0] = std::nextafter(p[1][0], 1e9f);  // almost none
    if (round % 4 == 3)
      for (int axis = 0; axis < 3; ++axis) p[2][axis] = 2 * p[1][axis] - p[0][axis];  // a line
    float pair_p[3], pair_q[3], alone_p[3], alone_q[3];
    stl_face_normals(p, q, pair_p, pair_q);
    stl_face_normal(p, alone_p);
    stl_face_normal(q, alone_q);
    ASSERT_EQ(std::memcmp(pair_p, alone_p, sizeof alone_p), 0) << "round " << round;
    ASSERT_EQ(std::memcmp(pair_q, alone_q, sizeof alone_q), 0) << "round " << round;
  }
}
#endif

}  // namespace
}  // namespace mvox
