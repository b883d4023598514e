// Gradient normals and the slice window they read: the window keeps exactly the last four
// slices and refuses what does not fit; streamed through the engine one slice behind, normals
// of a linear density are exactly minus its gradient per world unit, border vertices get the
// outward axis, and a sphere's normals point outwards.
#include "mvox/vertex_normals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <vector>

#include "mesh_capture.h"
#include "mvox/engine.h"
#include "mvox/slice_window.h"
#include "phantom_factory.h"
#include "simulated_scanner.h"
#include "mvox/stream_volume.h"

namespace mvox {
namespace {

constexpr double kPi = 3.14159265358979323846;

// --- SliceWindow ------------------------------------------------------------------------------

// Sample of slice z at (x, y), different for every voxel of the tests' small volumes.
std::uint16_t pattern(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return static_cast<std::uint16_t>(1000 * z + 37 * y + x);
}

TEST(SliceWindow, WorkspaceIsFourSlicesAndEverySizeBelowIsRefused) {
  EXPECT_EQ(slice_window_bytes(7, 5, SampleType::u8), 4u * 7 * 5);
  EXPECT_EQ(slice_window_bytes(7, 5, SampleType::u16), 4u * 7 * 5 * 2);
  EXPECT_EQ(slice_window_bytes(7, 5, SampleType::i16), 4u * 7 * 5 * 2);
  EXPECT_EQ(slice_window_bytes(7, 5, SampleType::f32), 4u * 7 * 5 * 4);
  EXPECT_EQ(slice_window_bytes(0, 5, SampleType::u8), 0u);
  EXPECT_EQ(slice_window_bytes(7, 0, SampleType::u8), 0u);
  const std::size_t bound = slice_window_bytes(7, 5, SampleType::u16);
  std::vector<unsigned char> memory(bound + 1);
  SliceWindow window;
  for (std::size_t bytes = 0; bytes < bound; ++bytes)
    ASSERT_EQ(window.init(memory.data(), bytes, 7, 5, SampleType::u16), Status::workspace_too_small)
        << bytes;
  EXPECT_EQ(window.init(nullptr, bound, 7, 5, SampleType::u16), Status::invalid_argument);
  // Any alignment will do.
  EXPECT_EQ(window.init(memory.data() + 1, bound, 7, 5, SampleType::u16), Status::ok);
}

// A stage that holds layers back (smoothing) asks about vertices some slices later: the window
// can hold more, a power of two at least as many as asked.
TEST(SliceWindow, ADeeperWindowHoldsThatManyOfTheLastSlices) {
  EXPECT_EQ(slice_window_slots(0), 4u);
  EXPECT_EQ(slice_window_slots(4), 4u);
  EXPECT_EQ(slice_window_slots(5), 8u);
  EXPECT_EQ(slice_window_slots(15), 16u);
  EXPECT_EQ(slice_window_slots(17), 32u);
  EXPECT_EQ(slice_window_bytes(7, 5, SampleType::u16, 15), 16u * 7 * 5 * 2);
  const std::uint32_t w = 7, h = 5, d = 40;
  std::vector<unsigned char> memory(slice_window_bytes(w, h, SampleType::u16, 13));
  SliceWindow window;
  ASSERT_EQ(window.init(memory.data(), memory.size() - 1, w, h, SampleType::u16, 13),
            Status::workspace_too_small);
  ASSERT_EQ(window.init(memory.data(), memory.size(), w, h, SampleType::u16, 13), Status::ok);
  EXPECT_EQ(window.slots(), 16u);
  std::vector<std::uint16_t> slice(std::size_t{w} * h);
  for (std::uint32_t z = 0; z < d; ++z) {
    for (std::uint32_t y = 0; y < h; ++y)
      for (std::uint32_t x = 0; x < w; ++x) slice[std::size_t{y} * w + x] = pattern(x, y, z);
    SliceView view{slice.data(), w, h, std::size_t{w} * 2, SampleType::u16};
    ASSERT_EQ(window.push(view), Status::ok);
    for (std::uint32_t held = 0; held <= z; ++held) {
      ASSERT_EQ(window.holds(held), held + 16 > z) << held << " after " << z;
      if (window.holds(held))
        ASSERT_EQ(window.sample(3, 2, held), pattern(3, 2, held)) << held << " after " << z;
    }
  }
}

TEST(SliceWindow, HoldsExactlyTheLastFourSlices) {
  const std::uint32_t w = 7, h = 5, d = 11;
  std::vector<unsigned char> memory(slice_window_bytes(w, h, SampleType::u16));
  SliceWindow window;
  ASSERT_EQ(window.init(memory.data(), memory.size(), w, h, SampleType::u16), Status::ok);
  EXPECT_FALSE(window.holds(0));
  // Rows padded to an odd stride and the slice buffer reused for every slice, as a reader does:
  // the window must copy, not point.
  const std::size_t stride = w * 2 + 3;
  std::vector<unsigned char> buffer(stride * h + 1);
  for (std::uint32_t z = 0; z < d; ++z) {
    for (std::uint32_t y = 0; y < h; ++y)
      for (std::uint32_t x = 0; x < w; ++x) {
        const std::uint16_t value = pattern(x, y, z);
        std::memcpy(buffer.data() + 1 + y * stride + x * 2, &value, 2);  // unaligned on purpose
      }
    ASSERT_EQ(window.push({buffer.data() + 1, w, h, stride, SampleType::u16}), Status::ok);
    ASSERT_EQ(window.slices(), z + 1);
    for (std::int64_t k = -2; k <= std::int64_t{z} + 2; ++k)
      EXPECT_EQ(window.holds(k), k >= 0 && k <= z && k + 4 > z) << "after " << z << ": " << k;
    for (std::uint32_t k = z >= 3 ? z - 3 : 0; k <= z; ++k) {
      const SliceView view = window.slice(k);
      EXPECT_EQ(view.width, w);
      EXPECT_EQ(view.height, h);
      EXPECT_EQ(view.type, SampleType::u16);
      for (std::uint32_t y = 0; y < h; ++y)
        for (std::uint32_t x = 0; x < w; ++x) {
          std::uint16_t value;
          std::memcpy(
              &value,
              static_cast<const unsigned char*>(view.samples) + y * view.row_stride_bytes + x * 2,
              2);
          ASSERT_EQ(value, pattern(x, y, k)) << x << "," << y << "," << k << " after " << z;
          ASSERT_EQ(window.sample(x, y, k), pattern(x, y, k));
        }
    }
    // Coordinates outside clamp to the border (and z to the newest slice).
    EXPECT_EQ(window.sample(-5, 2, z), pattern(0, 2, z));
    EXPECT_EQ(window.sample(w + 3, -1, z), pattern(w - 1, 0, z));
    EXPECT_EQ(window.sample(1, h, z + 7), pattern(1, h - 1, z));
  }
}

TEST(SliceWindow, PushRefusesWhatDoesNotFitAndChangesNothing) {
  const std::uint32_t w = 6, h = 4;
  std::vector<float> memory(slice_window_bytes(w, h, SampleType::f32) / 4);
  std::vector<float> slice(w * h, 2.5f), other(w * h * 4, -1.0f);
  SliceWindow window;
  EXPECT_EQ(window.push({slice.data(), w, h, w * 4, SampleType::f32}), Status::not_initialised);
  ASSERT_EQ(window.init(memory.data(), memory.size() * 4, w, h, SampleType::f32), Status::ok);
  ASSERT_EQ(window.push({slice.data(), w, h, w * 4, SampleType::f32}), Status::ok);
  EXPECT_EQ(window.push({other.data(), w + 1, h, (w + 1) * 4, SampleType::f32}),
            Status::slice_size_mismatch);
  EXPECT_EQ(window.push({other.data(), w, h + 1, w * 4, SampleType::f32}),
            Status::slice_size_mismatch);
  EXPECT_EQ(window.push({other.data(), w, h, w * 4, SampleType::u16}), Status::slice_size_mismatch);
  EXPECT_EQ(window.push({other.data(), w, h, w * 4, SampleType::i16}), Status::slice_size_mismatch);
  EXPECT_EQ(window.push({other.data(), w, h, w * 4 - 1, SampleType::f32}),
            Status::invalid_argument);  // rows would overlap
  EXPECT_EQ(window.push({nullptr, w, h, w * 4, SampleType::f32}), Status::invalid_argument);
  EXPECT_EQ(window.slices(), 1u);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) EXPECT_EQ(window.sample(x, y, 0), 2.5);
  // init() again starts a new volume.
  ASSERT_EQ(window.init(memory.data(), memory.size() * 4, w, h, SampleType::f32), Status::ok);
  EXPECT_EQ(window.slices(), 0u);
  EXPECT_FALSE(window.holds(0));
}

// --- Normals, streamed through the engine -----------------------------------------------------

// A volume in memory as a slice source, handing out every slice in one reused buffer (as a
// reader does), so that whoever keeps a slice past the next call reads the wrong one.
template <typename Sample>
class VolumeSource final : public SliceSource {
 public:
  VolumeSource(const test::Volume<Sample>& volume, SampleType type, const glm::vec3& spacing)
      : volume_(volume), buffer_(std::size_t{volume.width} * volume.height) {
    info_.width = volume.width;
    info_.height = volume.height;
    info_.depth = volume.depth;
    info_.type = type;
    for (int axis = 0; axis < 3; ++axis) info_.spacing[axis] = spacing[axis];
  }
  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override {
    if (next_z_ == volume_.depth) return false;
    std::memcpy(buffer_.data(), volume_.samples.data() + next_z_ * buffer_.size(),
                buffer_.size() * sizeof(Sample));
    ++next_z_;
    *slice = {buffer_.data(), info_.width, info_.height, info_.width * sizeof(Sample), info_.type};
    return true;
  }

 private:
  const test::Volume<Sample>& volume_;
  std::vector<Sample> buffer_;
  VolumeInfo info_;
  std::uint32_t next_z_ = 0;
};

// Computes every vertex's normal the moment the engine hands the vertex over, as a renderer or
// mesh writer would, both a batch at a time and one by one.
class NormalsSink final : public PolygonSink {
 public:
  explicit NormalsSink(const VertexNormals& normals) : normals_(normals) {}
  Status consume_vertices(const Vertex* vertices, std::size_t vertex_count) override {
    const std::size_t first = this->vertices.size();
    this->vertices.insert(this->vertices.end(), vertices, vertices + vertex_count);
    normals.resize(this->vertices.size());
    normals_.compute(vertices, vertex_count, normals.data() + first);
    for (std::size_t i = 0; i < vertex_count; ++i)
      single_call_mismatches += normals_(vertices[i]) != normals[first + i];
    return Status::ok;
  }
  Status consume_polygons(const Polygon*, std::size_t) override { return Status::ok; }

  std::vector<Vertex> vertices;
  std::vector<glm::vec3> normals;
  std::size_t single_call_mismatches = 0;

 private:
  const VertexNormals& normals_;
};

struct StreamedNormals {
  std::vector<Vertex> vertices;
  std::vector<glm::vec3> normals;
};

// Streams `source` through an engine with a slice window (stream_volume feeds the engine one
// slice behind) and returns every vertex with the normal computed when it arrived.
StreamedNormals stream_normals(SliceSource& source, double threshold,
                               SurfaceMethod method = SurfaceMethod::voxels) {
  const VolumeInfo& info = source.info();
  std::vector<unsigned char> window_memory(slice_window_bytes(info.width, info.height, info.type));
  SliceWindow window;
  EXPECT_EQ(
      window.init(window_memory.data(), window_memory.size(), info.width, info.height, info.type),
      Status::ok);
  const VertexNormals normals(
      window, glm::vec3(static_cast<float>(info.spacing[0]), static_cast<float>(info.spacing[1]),
                        static_cast<float>(info.spacing[2])));
  NormalsSink sink(normals);
  EngineOptions options;
  options.method = method;
  options.vertices_per_batch = 61;  // many batches, so normals are asked for mid-slice too
  test::Workspace workspace(engine_workspace_bytes(info.width, info.height, options));
  Engine engine;
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), info.width, info.height, threshold,
                        options, &sink),
            Status::ok);
  EXPECT_EQ(stream_volume(source, engine, {}, &window), Status::ok);
  EXPECT_EQ(window.slices(), info.depth);
  EXPECT_EQ(sink.single_call_mismatches, 0u);
  return {std::move(sink.vertices), std::move(sink.normals)};
}

// The voxel pair a vertex lies between: `low` and low + 1 along the vertex's axis.
struct VoxelPair {
  int axis = 0;
  std::int64_t low[3] = {};
};

VoxelPair voxel_pair(const Vertex& v) {
  VoxelPair pair;
  pair.axis = static_cast<int>(v.axis);
  const float coordinates[3] = {v.x, v.y, v.z};
  for (int k = 0; k < 3; ++k) pair.low[k] = static_cast<std::int64_t>(std::floor(coordinates[k]));
  return pair;
}

// The linear density of the next tests, in sample units per voxel step.
constexpr double kGradient[3] = {3, 5, -2};
double linear_density(std::int64_t x, std::int64_t y, std::int64_t z) {
  return kGradient[0] * x + kGradient[1] * y + kGradient[2] * z + 100;
}

template <typename Sample>
void expect_linear_density_normals(SampleType type, double offset) {
  const std::uint32_t w = 9, h = 8, d = 7;  // odd, asymmetric: an axis swap shows
  const glm::vec3 spacing(1, 1, 2);         // anisotropic: gradients are per world unit
  test::Volume<Sample> volume(w, h, d);
  for (std::uint32_t z = 0; z < d; ++z)
    for (std::uint32_t y = 0; y < h; ++y)
      for (std::uint32_t x = 0; x < w; ++x)
        volume.at(x, y, z) = static_cast<Sample>(linear_density(x, y, z) + offset);
  VolumeSource<Sample> source(volume, type, spacing);
  const StreamedNormals streamed = stream_normals(source, 123.5 + offset);  // a plane mid-volume

  // -gradient per world unit: (3, 5, -2) / (1, 1, 2), negated and normalised.
  const glm::dvec3 analytic = -glm::normalize(
      glm::dvec3(kGradient[0] / spacing.x, kGradient[1] / spacing.y, kGradient[2] / spacing.z));
  const std::int64_t extent[3] = {w, h, d};
  std::size_t interior = 0, border = 0, near_border = 0;
  for (std::size_t i = 0; i < streamed.vertices.size(); ++i) {
    const Vertex& v = streamed.vertices[i];
    const glm::vec3& n = streamed.normals[i];
    const VoxelPair pair = voxel_pair(v);
    const std::string where = "vertex (" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " +
                              std::to_string(v.z) + ") axis " + std::to_string(pair.axis);
    ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f) << where;
    const std::int64_t low = pair.low[pair.axis];
    if (low < 0 || low + 1 >= extent[pair.axis]) {
      // Between a voxel and the outside of the volume: the flat cap's outward axis, exactly.
      glm::vec3 axis(0.0f);
      axis[pair.axis] = v.inner_is_lower ? 1.0f : -1.0f;
      EXPECT_EQ(n, axis) << where;
      ++border;
      continue;
    }
    // Both voxels with all six neighbours inside the volume: the exact gradient.
    bool all_inside = true;
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 3; ++k) {
        const std::int64_t c = pair.low[k] + (side == 1 && k == pair.axis);
        all_inside = all_inside && c >= 1 && c + 1 < extent[k];
      }
    if (all_inside) {
      ++interior;
      EXPECT_NEAR(n.x, analytic.x, 1e-5) << where;
      EXPECT_NEAR(n.y, analytic.y, 1e-5) << where;
      EXPECT_NEAR(n.z, analytic.z, 1e-5) << where;
      continue;
    }
    // Next to the border the differences replicate the border sample (one-sided, halved), as
    // documented; recomputed here from the whole volume.
    ++near_border;
    glm::dvec3 sum(0.0);
    for (int side = 0; side < 2; ++side) {
      std::int64_t c[3] = {pair.low[0], pair.low[1], pair.low[2]};
      c[pair.axis] += side;
      for (int k = 0; k < 3; ++k) {
        std::int64_t up[3] = {c[0], c[1], c[2]}, down[3] = {c[0], c[1], c[2]};
        up[k] = std::min(up[k] + 1, extent[k] - 1);
        down[k] = std::max<std::int64_t>(down[k] - 1, 0);
        sum[k] +=
            (linear_density(up[0], up[1], up[2]) - linear_density(down[0], down[1], down[2])) /
            (2 * spacing[k]);
      }
    }
    const glm::dvec3 expected = -glm::normalize(sum);
    EXPECT_NEAR(n.x, expected.x, 1e-5) << where;
    EXPECT_NEAR(n.y, expected.y, 1e-5) << where;
    EXPECT_NEAR(n.z, expected.z, 1e-5) << where;
  }
  EXPECT_GT(interior, 20u);
  EXPECT_GT(border, 10u);
  EXPECT_GT(near_border, 10u);
}

TEST(VertexNormals, ALinearDensityGivesMinusItsGradientPerWorldUnit) {
  expect_linear_density_normals<float>(SampleType::f32, 0);
  expect_linear_density_normals<std::uint16_t>(SampleType::u16, 0);
  expect_linear_density_normals<std::uint8_t>(SampleType::u8, 0);
  expect_linear_density_normals<std::int16_t>(SampleType::i16, -200);  // negative samples
}

// Marching cubes puts vertices anywhere along their edges, and the gradient is interpolated to
// the vertex. On x^2 + 3y + z central differences are exact, (2x, 3, 1), and linear in x, so
// the interpolated gradient is the density's own gradient at the vertex; an average of the two
// voxels' gradients (right only at midpoints) would be off wherever t differs from 1/2.
TEST(VertexNormals, MarchingCubesVerticesGetTheGradientInterpolatedToWhereTheySit) {
  const std::uint32_t w = 9, h = 8, d = 7;
  test::Volume<float> volume(w, h, d);
  for (std::uint32_t z = 0; z < d; ++z)
    for (std::uint32_t y = 0; y < h; ++y)
      for (std::uint32_t x = 0; x < w; ++x)
        volume.at(x, y, z) = static_cast<float>(x * x + 3 * y + z);
  VolumeSource<float> source(volume, SampleType::f32, {1, 1, 1});
  const StreamedNormals streamed = stream_normals(source, 30.3, SurfaceMethod::cubes);
  const std::int64_t extent[3] = {w, h, d};
  std::size_t checked = 0, off_midpoint = 0;
  for (std::size_t i = 0; i < streamed.vertices.size(); ++i) {
    const Vertex& v = streamed.vertices[i];
    const VoxelPair pair = voxel_pair(v);
    bool all_inside = true;
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 3; ++k) {
        const std::int64_t c = pair.low[k] + (side == 1 && k == pair.axis);
        all_inside = all_inside && c >= 1 && c + 1 < extent[k];
      }
    if (!all_inside) continue;
    ++checked;
    const float along = pair.axis == 0 ? v.x : pair.axis == 1 ? v.y : v.z;
    off_midpoint += std::abs(along - std::floor(along) - 0.5f) > 0.1f;
    const glm::dvec3 expected = -glm::normalize(glm::dvec3(2.0 * v.x, 3, 1));
    const glm::vec3& n = streamed.normals[i];
    EXPECT_NEAR(n.x, expected.x, 1e-5) << v.x << "," << v.y << "," << v.z;
    EXPECT_NEAR(n.y, expected.y, 1e-5) << v.x << "," << v.y << "," << v.z;
    EXPECT_NEAR(n.z, expected.z, 1e-5) << v.x << "," << v.y << "," << v.z;
  }
  EXPECT_GT(checked, 20u);
  EXPECT_GT(off_midpoint, 10u);
}

TEST(VertexNormals, WhereTheGradientVanishesTheOutwardAxisIsUsed) {
  // Slices alternately inner and outer (z = 0, 2, 4 inner), each uniform: at a vertex between
  // slices z and z + 1 the central differences at both voxels are 0 - 0 or 1 - 1, so the
  // gradient vanishes and only the fallback can give a normal (normalising would give NaN).
  // Every other vertex is on the volume's border. All normals are the outward axis, exactly.
  test::Volume<std::uint8_t> volume(5, 4, 5);
  for (std::uint32_t z = 0; z < 5; z += 2)
    for (std::uint32_t y = 0; y < 4; ++y)
      for (std::uint32_t x = 0; x < 5; ++x) volume.at(x, y, z) = 1;
  VolumeSource<std::uint8_t> source(volume, SampleType::u8, {1, 1, 1});
  const StreamedNormals streamed = stream_normals(source, 1);
  std::size_t vanishing = 0;
  for (std::size_t i = 0; i < streamed.vertices.size(); ++i) {
    const Vertex& v = streamed.vertices[i];
    glm::vec3 axis(0.0f);
    axis[static_cast<int>(v.axis)] = v.inner_is_lower ? 1.0f : -1.0f;
    EXPECT_EQ(streamed.normals[i], axis) << v.x << "," << v.y << "," << v.z;
    // Between slices 0..1 and 3..4 the border replication breaks the symmetry; 1..2 and 2..3
    // are the vanishing ones.
    vanishing += v.axis == Axis::z && v.z > 1 && v.z < 3;
  }
  EXPECT_EQ(vanishing, 2u * 5 * 4);
  // Three inner slices: each has a top and a bottom (20 vertices each) and a rim against the
  // volume's sides (2 * (5 + 4) vertices).
  EXPECT_EQ(streamed.vertices.size(), 3u * (2 * 20 + 2 * (5 + 4)));
}

TEST(VertexNormals, ASpheresNormalsPointOutwards) {
  // Odd, asymmetric grid; the sphere (radius 0.4 * 33 = 13.2) sits at the grid centre.
  const sim::Grid grid{41, 37, 33};
  const auto phantom = sim::make_phantom("sphere", grid, 0);
  const sim::ScanOptions scan = sim::default_scan_options(SampleType::u8);
  sim::SimulatedScanner scanner(*phantom, scan);
  const StreamedNormals streamed = stream_normals(scanner, sim::sample_threshold(0.5, scan));
  const sim::Point3 c = sim::grid_centre(grid);
  const glm::dvec3 centre(c.x, c.y, c.z);
  ASSERT_GT(streamed.vertices.size(), 1000u);
  double angle_sum = 0, angle_max = 0;
  std::size_t inward = 0;
  for (std::size_t i = 0; i < streamed.vertices.size(); ++i) {
    const Vertex& v = streamed.vertices[i];
    const glm::dvec3 radial = glm::normalize(glm::dvec3(v.x, v.y, v.z) - centre);
    const double cosine = glm::dot(glm::dvec3(streamed.normals[i]), radial);
    inward += !(cosine > 0);
    const double angle = std::acos(std::min(1.0, cosine)) * 180 / kPi;
    angle_sum += angle;
    angle_max = std::max(angle_max, angle);
  }
  const double angle_mean = angle_sum / static_cast<double>(streamed.vertices.size());
  // What a normal that ignored the densities would score: each vertex's outward axis.
  double axis_sum = 0;
  for (const Vertex& v : streamed.vertices) {
    const glm::dvec3 radial = glm::normalize(glm::dvec3(v.x, v.y, v.z) - centre);
    glm::dvec3 axis(0.0);
    axis[static_cast<int>(v.axis)] = v.inner_is_lower ? 1 : -1;
    axis_sum += std::acos(std::min(1.0, glm::dot(axis, radial))) * 180 / kPi;
  }
  const double axis_mean = axis_sum / static_cast<double>(streamed.vertices.size());
  EXPECT_EQ(inward, 0u);
  // Central differences of a binary volume are small integers (each component of the summed
  // differences at the two voxels is -2 .. 2), so the normals are quantised to a few dozen
  // directions. The error that leaves does not shrink with the radius: the mean angle to the
  // radial direction measured 13.2 .. 14.7 degrees for spheres of radius 8 .. 38 on grids like
  // this one (13.6 here), the largest 34 .. 44. The bounds add a few degrees to the worst of
  // those, and stay far below the 45 degrees that the outward axis alone scores, so a normal
  // that ignored the gradient, swapped two axes or read a stale slice would fail.
  EXPECT_LT(angle_mean, 17.0);
  EXPECT_LT(angle_max, 50.0);
  EXPECT_GT(axis_mean, 40.0);
}

}  // namespace
}  // namespace mvox
