// The mesh writer's per-batch work on its fast paths, against the plain loops it replaced:
// scan_polygons (every batch's sizes and largest index), VertexPlacement::place (every
// vertex's world position) and CornerPlacement (STL's corners; stl_triangle_records_test has
// the rest of STL's records). Both must give exactly what the plain loops give, whatever the slots
// past a polygon's size hold and wherever a vertex leaves float's range. Also the Python module's
// appends into numpy's arrays (append_polygons, append_vertex_positions), against their plain
// loops.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mvox/mesh.h"
#include "write/mesh/corner_placement.h"
#include "write/mesh/mesh_arrays.h"
#include "write/mesh/polygon_scan.h"
#include "write/mesh/vertex_placement.h"
#include "write/mesh/world_transform.h"

namespace mvox {
namespace {

// Polygons of every size 0..255 (mostly 3 to 7), indices of any magnitude, and the slots past
// the size and the padding after the count filled with noise that must not count.
std::vector<Polygon> noisy_polygons(std::mt19937& random, std::size_t count) {
  std::vector<Polygon> polygons(count);
  for (Polygon& polygon : polygons) {
    unsigned char bytes[sizeof(Polygon)];
    for (unsigned char& byte : bytes) byte = static_cast<unsigned char>(random());
    std::memcpy(static_cast<void*>(&polygon), bytes, sizeof bytes);
    const unsigned pick = random() % 16;
    polygon.vertex_count = static_cast<std::uint8_t>(pick < 12 ? 3 + pick % 5 : random() % 256);
    // Indices of 0 to 32 bits, so that the largest ones have the top bit set (an unsigned
    // maximum, not a signed one).
    const unsigned bits = random() % 33;
    const std::uint32_t mask = bits == 32 ? 0xffffffffu : (1u << bits) - 1;
    for (int k = 0; k < polygon.vertex_count && k < kMaxPolygonVertices; ++k)
      polygon.vertices[k] = static_cast<std::uint32_t>(random()) & mask;
  }
  return polygons;
}

TEST(PolygonScan, AgreesWithTheSlotBySlotLoopWhateverTheUnusedSlotsHold) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (!__builtin_cpu_supports("avx2"))
    GTEST_SKIP() << "no AVX2 on this CPU: scan_polygons is the slot-by-slot loop itself here";
#endif
  std::mt19937 random(20261127);
  for (int batch = 0; batch < 2000; ++batch) {
    const std::vector<Polygon> polygons = noisy_polygons(random, random() % 40);
    const PolygonScan fast = scan_polygons(polygons.data(), polygons.size());
    const PolygonScan plain = scan_polygons_portable(polygons.data(), polygons.size());
    ASSERT_EQ(fast.sizes_ok, plain.sizes_ok) << "batch " << batch;
    ASSERT_EQ(fast.highest, plain.highest) << "batch " << batch;
  }
}

TEST(PolygonScan, CountsOnlyEachPolygonsOwnSlotsAndFlagsEverySizeOutOfRange) {
  Polygon triangle;
  triangle.vertex_count = 3;
  for (std::uint32_t& slot : triangle.vertices) slot = 0xffffffffu;  // past the size: noise
  triangle.vertices[0] = 5;
  triangle.vertices[1] = 9;
  triangle.vertices[2] = 7;
  PolygonScan scan = scan_polygons(&triangle, 1);
  EXPECT_TRUE(scan.sizes_ok);
  EXPECT_EQ(scan.highest, 9u);
  for (unsigned size : {0u, 1u, 2u, 8u, 255u}) {
    Polygon polygon = triangle;
    polygon.vertex_count = static_cast<std::uint8_t>(size);
    EXPECT_FALSE(scan_polygons(&polygon, 1).sizes_ok) << size;
  }
  for (unsigned size = 3; size <= kMaxPolygonVertices; ++size) {
    Polygon polygon = triangle;
    polygon.vertex_count = static_cast<std::uint8_t>(size);
    scan = scan_polygons(&polygon, 1);
    EXPECT_TRUE(scan.sizes_ok) << size;
    EXPECT_EQ(scan.highest, size > 3 ? 0xffffffffu : 9u) << size;
  }
  scan = scan_polygons(nullptr, 0);
  EXPECT_TRUE(scan.sizes_ok);
  EXPECT_EQ(scan.highest, 0u);
}

// The floats of the plain placement: float(origin + spacing * v) per axis, in double.
void expect_placed_as_plain(const WorldTransform& transform, const std::vector<Vertex>& vertices,
                            const std::vector<WorldVertex>& placed, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    const Vector3d world =
        transform.axis_aligned_position(vertices[i].x, vertices[i].y, vertices[i].z);
    for (int axis = 0; axis < 3; ++axis) {
      const float expected = static_cast<float>(world[axis]);
      // Bit for bit: +0 and -0 differ in a file.
      ASSERT_EQ(std::memcmp(&placed[i].position[axis], &expected, sizeof expected), 0)
          << "vertex " << i << " axis " << axis << ": " << placed[i].position[axis] << " vs "
          << expected;
    }
  }
}

TEST(VertexPlacement, AxisAlignedBatchesPlaceBitForBitAsThePlainSumForAnySpacingAndOrigin) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-0.5f, 4000.0f);
  struct Case {
    std::array<double, 3> spacing, origin;
  };
  const Case cases[] = {
      {{1, 1, 1}, {0, 0, 0}},                     // a raw volume's default
      {{1, 1, 1}, {-0.0, 0, -0.0}},               // -0 origins keep -0 coordinates
      {{0.3, 0.7, 2.5}, {-120.25, 33.5, 1e-3}},   // a CT series
      {{1.0 / 3.0, 1e-4, 17.0}, {7e6, -0.0, 0}},  // roundings in every term
  };
  for (const Case& c : cases) {
    WorldTransform transform;
    for (int axis = 0; axis < 3; ++axis) {
      transform.spacing[axis] = c.spacing[axis];
      transform.origin[axis] = c.origin[axis];
    }
    transform.check("test");
    std::vector<Vertex> vertices(5000);
    for (Vertex& v : vertices) {
      v = {coordinate(random), coordinate(random), coordinate(random)};
      v.axis = static_cast<Axis>(random() % 3);
      v.inner_is_lower = random() % 2;
    }
    vertices[0] = {-0.0f, 0.0f, -0.0f};  // signed zeros, on every path
    vertices[1] = {-0.5f, -0.5f, -0.5f};
    for (bool normals : {false, true}) {
      const VertexPlacement placement(transform, normals);
      const std::vector<glm::vec3> given(vertices.size(), glm::vec3(0.6f, -0.8f, 0.0f));
      std::vector<WorldVertex> placed(vertices.size());
      ASSERT_EQ(placement.place(vertices.data(), normals ? given.data() : nullptr, vertices.size(),
                                placed.data()),
                vertices.size());
      expect_placed_as_plain(transform, vertices, placed, vertices.size());
      if (normals) {
        for (std::size_t i = 0; i < vertices.size(); ++i)
          for (int axis = 0; axis < 3; ++axis) ASSERT_EQ(placed[i].normal[axis], given[i][axis]);
      }
    }
  }
}

TEST(VertexPlacement, AFastBatchNamesTheSameFirstVertexBeyondFloatsRangeAsThePlainLoop) {
  WorldTransform transform;
  transform.spacing = {1.0, 1e36, 1.0};  // y beyond 340 leaves float's range
  transform.check("test");
  for (bool normals : {false, true}) {
    const VertexPlacement placement(transform, normals);
    for (std::size_t outside : {0u, 1u, 7u, 4095u}) {
      std::vector<Vertex> vertices(4096, Vertex{1.5f, 2.0f, 3.0f});
      vertices[outside].y = 400.0f;
      vertices.back().y = 500.0f;  // a later one changes nothing
      const std::vector<glm::vec3> given(vertices.size(), glm::vec3(0, 0, 1));
      std::vector<WorldVertex> placed(vertices.size());
      EXPECT_EQ(placement.place(vertices.data(), normals ? given.data() : nullptr, vertices.size(),
                                placed.data()),
                outside);
      expect_placed_as_plain(transform, vertices, placed, outside);
    }
  }
}

// Binary PLY without normals takes the positions alone, placed straight into its buffer
// (place_positions): the bytes of place()'s floats, little-endian, 12 a vertex, never past the
// slack asked for, and the same first vertex named beyond float's range; on identity,
// axis-aligned and rotated axes.
TEST(VertexPlacement, PositionsAloneAreThePlacedFloatsAndStayInTheirRoom) {
  WorldTransform identity, negative_zero, spaced, rotated, beyond;
  negative_zero.origin = {-0.0, 0.0, -0.0};
  spaced.spacing = {0.3, 0.7, 2.5};
  spaced.origin = {-120.25, 33.5, 1e-3};
  rotated.axes = {{{0, -1, 0}, {-1, 0, 0}, {0, 0.1, 1}}};
  beyond.spacing = {1.0, 1e36, 1.0};  // y beyond 340 leaves float's range
  std::mt19937 random(11);
  std::uniform_real_distribution<float> coordinate(-0.5f, 300.0f);
  std::vector<Vertex> vertices(3001);
  for (Vertex& v : vertices) {
    v = {coordinate(random), coordinate(random), coordinate(random)};
    v.axis = static_cast<Axis>(random() % 3);
  }
  vertices[0] = {-0.0f, 0.0f, -0.0f};
  vertices[2999].y = 400.0f;  // only `beyond` takes it out of float's range
  for (const WorldTransform* transform : {&identity, &negative_zero, &spaced, &rotated, &beyond}) {
    transform->check("test");
    const VertexPlacement placement(*transform, false);
    for (std::size_t count : {std::size_t{1}, std::size_t{2}, vertices.size()}) {
      std::vector<WorldVertex> placed(count);
      const std::size_t placed_count =
          placement.place(vertices.data(), nullptr, count, placed.data());
      constexpr unsigned char kGuard = 0x5a;
      const std::size_t room = count * 12 + VertexPlacement::kPositionSlack;
      std::vector<unsigned char> records(room + 16, kGuard);
      EXPECT_EQ(placement.place_positions(vertices.data(), count, records.data()), placed_count);
      for (std::size_t i = room; i < records.size(); ++i)
        ASSERT_EQ(records[i], kGuard) << "past the room, byte " << i - room;
      for (std::size_t i = 0; i < placed_count; ++i)
        ASSERT_EQ(std::memcmp(&records[12 * i], placed[i].position, 12), 0) << "vertex " << i;
    }
  }
}

// A coordinate that is not finite is refused on every fast path as by the plain loop: on the
// identity path (a raw volume's default), on the axis-aligned one, and for corners on rotated
// axes. (The engine never makes one; the check keeps the conversion to float defined.)
TEST(VertexPlacement, ACoordinateThatIsNotFiniteIsNamedOnEveryPath) {
  WorldTransform identity, spaced, rotated;
  spaced.spacing = {0.5, 2.0, 3.0};
  spaced.origin = {1.0, -2.0, 0.25};
  rotated.axes = {{{0, -1, 0}, {-1, 0, 0}, {0, 0.1, 1}}};
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  for (const WorldTransform* transform : {&identity, &spaced, &rotated}) {
    transform->check("test");
    const VertexPlacement placement(*transform, false);
    const CornerPlacement corners(*transform);
    for (float value : bad) {
      for (int axis = 0; axis < 3; ++axis) {
        std::vector<Vertex> vertices(6, Vertex{1.5f, 2.0f, 3.0f});
        float* coordinate[3] = {&vertices[3].x, &vertices[3].y, &vertices[3].z};
        *coordinate[axis] = value;
        std::vector<WorldVertex> placed(vertices.size());
        if (transform->is_axis_aligned()) {
          EXPECT_EQ(placement.place(vertices.data(), nullptr, vertices.size(), placed.data()), 3u)
              << value << " on axis " << axis;
        }
        float corner_positions[6][4];
        EXPECT_FALSE(corners.place(vertices.data(), 6, corner_positions))
            << value << " on axis " << axis;
        EXPECT_TRUE(corners.place(vertices.data(), 3, corner_positions));
      }
    }
  }
}

// STL's corners are placed a polygon at a time by CornerPlacement: the floats of
// WorldTransform::position() itself, for rotated and mirrored axes too, and -0 origins.
TEST(CornerPlacement, CornersAreWherePositionPutsThemBitForBitOnAnyAxes) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> coordinate(-0.5f, 600.0f);
  std::uniform_real_distribution<double> component(-1.0, 1.0);
  std::vector<WorldTransform> transforms(5);
  transforms[1].spacing = {0.3, 0.7, 2.5};
  transforms[1].origin = {-0.0, 12.5, -7e3};  // position() turns -0 + -0 into +0
  transforms[4].spacing = {0.3, 0.7, 2.5};
  transforms[4].origin = {-120.25, 0.0, 33.5};
  transforms[2].axes = {{{0, -1, 0}, {-1, 0, 0}, {0, 0.1, 1}}};  // mirrored, sheared
  transforms[2].origin = {10.25, -20, 3.5};
  for (auto& row : transforms[3].axes)  // any axes that span space
    for (double& value : row) value = component(random);
  transforms[3].spacing = {1.0 / 3.0, 1e-3, 17.0};
  for (const WorldTransform& transform : transforms) {
    transform.check("test");
    const CornerPlacement corners(transform);
    std::vector<Vertex> vertices(kMaxPolygonVertices);
    for (int round = 0; round < 500; ++round) {
      for (Vertex& v : vertices) v = {coordinate(random), coordinate(random), coordinate(random)};
      if (round == 0) vertices[0] = {-0.0f, 0.0f, -0.0f};
      float placed[kMaxPolygonVertices][4];
      const int count = 1 + round % kMaxPolygonVertices;
      ASSERT_TRUE(corners.place(vertices.data(), count, placed));
      for (int i = 0; i < count; ++i) {
        ASSERT_EQ(placed[i][3], 0.0f) << "vertex " << i << ": the row's fourth float";
        const Vector3d world = transform.position(vertices[i].x, vertices[i].y, vertices[i].z);
        for (int axis = 0; axis < 3; ++axis) {
          const float expected = static_cast<float>(world[axis]);
          ASSERT_EQ(std::memcmp(&placed[i][axis], &expected, sizeof expected), 0)
              << "vertex " << i << " axis " << axis;
        }
      }
    }
  }
  WorldTransform far;
  far.spacing = {1.0, 1.0, 1e36};  // z beyond 340 leaves float's range
  far.check("test");
  const Vertex vertices[2] = {{1.0f, 2.0f, 3.0f}, {1.0f, 2.0f, 400.0f}};
  float placed[2][4];
  const CornerPlacement corners(far);
  EXPECT_TRUE(corners.place(vertices, 1, placed));
  EXPECT_FALSE(corners.place(vertices, 2, placed));
}

// Batches of 0 to 40 polygons of 3 to 7 vertices (the engine's sizes, which MeshWriter has
// checked before it appends), and every 25th of up to 5,000 (the fast appends stage what they
// write and stream it out a few KiB at a time), appended one after the other so that the
// offsets run on across batches and each batch starts at another place in a 32-byte block; and
// vertices with noise in the bytes after x, y and z: the fast appends give the arrays the plain
// loops give, element for element.
TEST(MeshArraysAppends, GiveWhatThePlainLoopsGiveBatchAfterBatch) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (!__builtin_cpu_supports("avx2"))
    GTEST_SKIP() << "no AVX2 on this CPU: the appends are the plain loops themselves here";
#endif
  std::mt19937 random(20261128);
  MeshArrays fast, plain;
  for (int batch = 0; batch < 500; ++batch) {
    const bool large = batch % 25 == 0;
    std::vector<Polygon> polygons = noisy_polygons(random, random() % (large ? 5001 : 41));
    for (Polygon& polygon : polygons) polygon.vertex_count = 3 + random() % 5;
    append_polygons(fast, polygons.data(), polygons.size());
    append_polygons_portable(plain, polygons.data(), polygons.size());

    std::vector<Vertex> vertices(random() % (large ? 5001 : 41));
    for (Vertex& vertex : vertices) {
      unsigned char bytes[sizeof(Vertex)];
      for (unsigned char& byte : bytes) byte = static_cast<unsigned char>(random());
      std::memcpy(static_cast<void*>(&vertex), bytes, sizeof bytes);
    }
    append_vertex_positions(fast, vertices.data(), vertices.size());
    append_vertex_positions_portable(plain, vertices.data(), vertices.size());

    ASSERT_EQ(fast.polygon_offsets.size(), plain.polygon_offsets.size()) << "batch " << batch;
    ASSERT_EQ(fast.polygon_indices.size(), plain.polygon_indices.size()) << "batch " << batch;
    ASSERT_EQ(fast.vertices.size(), plain.vertices.size()) << "batch " << batch;
    ASSERT_EQ(plain.polygon_offsets.data()[plain.polygon_offsets.size() - 1],
              static_cast<std::int64_t>(plain.polygon_indices.size()));
    ASSERT_EQ(0, std::memcmp(fast.polygon_offsets.data(), plain.polygon_offsets.data(),
                             plain.polygon_offsets.size() * sizeof(std::int64_t)))
        << "batch " << batch;
    ASSERT_EQ(0, std::memcmp(fast.polygon_indices.data(), plain.polygon_indices.data(),
                             plain.polygon_indices.size() * sizeof(std::int32_t)))
        << "batch " << batch;
    ASSERT_EQ(0, std::memcmp(fast.vertices.data(), plain.vertices.data(),
                             plain.vertices.size() * sizeof(float)))
        << "batch " << batch;
  }
  // Every place in a 32-byte block for a large batch to start, so that the staged appends
  // flush from each: t leading triangles (3t indices) and t leading vertices (3t floats) put
  // the next batch at each of the 8 places as t runs from 0 to 7, 3 being prime to 8.
  for (int t = 0; t < 8; ++t) {
    MeshArrays fast_t, plain_t;
    std::vector<Polygon> lead = noisy_polygons(random, t);
    for (Polygon& polygon : lead) polygon.vertex_count = 3;
    std::vector<Polygon> polygons = noisy_polygons(random, 3000);
    for (Polygon& polygon : polygons) polygon.vertex_count = 3 + random() % 5;
    std::vector<Vertex> vertices(t + 3001);
    for (Vertex& vertex : vertices) vertex.x = static_cast<float>(random());
    for (MeshArrays* arrays : {&fast_t, &plain_t}) {
      const bool fast_one = arrays == &fast_t;
      (fast_one ? append_polygons : append_polygons_portable)(*arrays, lead.data(), lead.size());
      (fast_one ? append_polygons : append_polygons_portable)(*arrays, polygons.data(),
                                                              polygons.size());
      (fast_one ? append_vertex_positions : append_vertex_positions_portable)(
          *arrays, vertices.data(), static_cast<std::size_t>(t));
      (fast_one ? append_vertex_positions : append_vertex_positions_portable)(
          *arrays, vertices.data() + t, vertices.size() - t);
    }
    ASSERT_EQ(fast_t.polygon_indices.size(), plain_t.polygon_indices.size());
    ASSERT_EQ(fast_t.vertices.size(), plain_t.vertices.size());
    EXPECT_EQ(0, std::memcmp(fast_t.polygon_indices.data(), plain_t.polygon_indices.data(),
                             plain_t.polygon_indices.size() * sizeof(std::int32_t)))
        << t << " triangles ahead";
    EXPECT_EQ(0, std::memcmp(fast_t.polygon_offsets.data(), plain_t.polygon_offsets.data(),
                             plain_t.polygon_offsets.size() * sizeof(std::int64_t)))
        << t << " triangles ahead";
    EXPECT_EQ(0, std::memcmp(fast_t.vertices.data(), plain_t.vertices.data(),
                             plain_t.vertices.size() * sizeof(float)))
        << t << " vertices ahead";
  }
  // The plain loops themselves: each polygon's own slots, each vertex's x, y and z.
  Polygon pentagon = noisy_polygons(random, 1)[0];
  pentagon.vertex_count = 5;
  Vertex vertex;
  vertex.x = 1.5f;
  vertex.y = -2.0f;
  vertex.z = 7.25f;
  MeshArrays one;
  append_polygons_portable(one, &pentagon, 1);
  append_vertex_positions_portable(one, &vertex, 1);
  ASSERT_EQ(one.polygon_indices.size(), 5u);
  for (int k = 0; k < 5; ++k)
    EXPECT_EQ(static_cast<std::uint32_t>(one.polygon_indices.data()[k]), pentagon.vertices[k]);
  ASSERT_EQ(one.polygon_offsets.size(), 2u);
  EXPECT_EQ(one.polygon_offsets.data()[1], 5);
  ASSERT_EQ(one.vertices.size(), 3u);
  EXPECT_EQ(one.vertices.data()[0], 1.5f);
  EXPECT_EQ(one.vertices.data()[1], -2.0f);
  EXPECT_EQ(one.vertices.data()[2], 7.25f);
}

}  // namespace
}  // namespace mvox
