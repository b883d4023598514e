// The renderer as the engine's sink, end to end: a phantom streamed through a slice window and
// the engine into a RenderSink gives a silhouette of the right size and place, shows the near
// side, and the picture does not depend on whether frames are read while it grows.
#include "mvox/render_sink.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "mvox/engine.h"
#include "mvox/slice_window.h"
#include "mvox/vertex_normals.h"
#include "mvox/zbuffer_renderer.h"
#include "shapes.h"
#include "simulated_scanner.h"
#include "mvox/stream_volume.h"
#include "mvox/workspace_buffer.h"

namespace mvox {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(VolumeBounds, HalfAVoxelBeyondTheOuterVoxelCentres) {
  VolumeInfo info;
  info.width = 7;
  info.height = 5;
  info.depth = 6;
  info.spacing[0] = 0.5;
  info.spacing[1] = 2;
  info.spacing[2] = 1.25;
  info.origin[0] = -3;
  info.origin[1] = 10;
  info.origin[2] = 0.5;
  glm::vec3 lo, hi;
  volume_bounds(info, &lo, &hi);
  EXPECT_FLOAT_EQ(lo.x, -3 - 0.25f);
  EXPECT_FLOAT_EQ(hi.x, -3 + 6.5f * 0.5f);
  EXPECT_FLOAT_EQ(lo.y, 10 - 1.0f);
  EXPECT_FLOAT_EQ(hi.y, 10 + 4.5f * 2);
  EXPECT_FLOAT_EQ(lo.z, 0.5f - 0.625f);
  EXPECT_FLOAT_EQ(hi.z, 0.5f + 5.5f * 1.25f);
}

// Where the renderer puts a world point: pixel position (y down) and depth 0 .. 1, by the
// OpenGL conventions camera.h states.
glm::vec3 project(const Camera& camera, const glm::vec3& p) {
  const glm::vec4 clip = camera.world_to_clip * glm::vec4(p, 1.0f);
  const glm::vec3 ndc = glm::vec3(clip) / clip.w;
  return {(ndc.x + 1) * 0.5f * camera.width, (1 - ndc.y) * 0.5f * camera.height,
          (ndc.z + 1) * 0.5f};
}

struct Picture {
  Camera camera;
  std::vector<std::uint8_t> pixels;
  std::vector<float> depths;
  std::uint32_t frames = 0;
};

// Scans `phantom` and streams it, through a slice window and an engine sending polygons by
// value, into a RenderSink over a renderer fitted orthographically to the volume's bounds.
// `after_slice` sees the renderer after every slice the engine has taken.
Picture render(const sim::Phantom& phantom, const sim::ScanOptions& scan, const ViewOptions& view,
               bool smooth,
               const std::function<void(const ZBufferRenderer&)>& after_slice = nullptr) {
  sim::SimulatedScanner scanner(phantom, scan);
  const VolumeInfo& info = scanner.info();
  Picture picture;
  glm::vec3 lo, hi;
  volume_bounds(info, &lo, &hi);
  picture.camera = fit_camera(lo, hi, view, 256, 192);
  std::vector<float> image_memory(zbuffer_workspace_bytes(256, 192) / sizeof(float) + 1);
  ZBufferRenderer renderer;
  EXPECT_EQ(renderer.init(image_memory.data(), image_memory.size() * sizeof(float), picture.camera),
            Status::ok);
  std::vector<unsigned char> window_memory(slice_window_bytes(info.width, info.height, info.type));
  SliceWindow window;
  EXPECT_EQ(
      window.init(window_memory.data(), window_memory.size(), info.width, info.height, info.type),
      Status::ok);
  const glm::vec3 spacing(info.spacing[0], info.spacing[1], info.spacing[2]);
  const glm::vec3 origin(info.origin[0], info.origin[1], info.origin[2]);
  const VertexNormals normals(window, spacing);
  RenderSink sink(renderer, spacing, origin, smooth ? &normals : nullptr);
  EngineOptions options;
  options.polygon_geometry = true;
  options.polygons_per_batch = 97;  // many batches per slice
  WorkspaceBuffer workspace(engine_workspace_bytes(info.width, info.height, options));
  Engine engine;
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), info.width, info.height,
                        sim::sample_threshold(0.5, scan), options, &sink),
            Status::ok);
  auto count_frame = [&](std::uint32_t) {
    ++picture.frames;
    if (after_slice) after_slice(renderer);
  };
  EXPECT_EQ(stream_volume(scanner, engine, SliceProgress::of(count_frame), &window), Status::ok);
  EXPECT_EQ(renderer.counters().polygons, engine.counters().polygons);
  const std::size_t n = std::size_t{renderer.width()} * renderer.height();
  picture.pixels.assign(renderer.pixels(), renderer.pixels() + n);
  picture.depths.assign(renderer.depths(), renderer.depths() + n);
  return picture;
}

std::size_t covered(const Picture& picture) {
  std::size_t n = 0;
  for (float depth : picture.depths) n += std::isfinite(depth);
  return n;
}

// Pixels per world unit along the image's x and y axes: for an orthographic camera, half the
// image size times the length of the projection's first (second) row.
glm::vec2 pixels_per_unit(const Camera& camera) {
  const glm::mat4& m = camera.world_to_clip;  // column-major: m[column][row]
  return {0.5f * camera.width * glm::length(glm::vec3(m[0][0], m[1][0], m[2][0])),
          0.5f * camera.height * glm::length(glm::vec3(m[0][1], m[1][1], m[2][1]))};
}

std::size_t pixel_index(const Picture& picture, const glm::vec3& position) {
  return static_cast<std::size_t>(position.y) * picture.camera.width +
         static_cast<std::size_t>(position.x);
}

TEST(RenderSink, ASpheresSilhouetteHasItsRadiusAndItsPlaceAndShowsTheNearSide) {
  // Off the grid's centre, so that the silhouette's place tests origin and spacing; the centre
  // on a voxel centre, so that the voxelised sphere is symmetric about it.
  const sim::Grid grid{49, 45, 41};
  const sim::Point3 c{21, 24, 19};
  const double radius = 14.3;
  const sim::Sphere sphere(grid, c, radius);
  struct Case {
    glm::vec3 spacing;
    glm::vec3 origin;
    ViewOptions view;
  };
  ViewOptions above;
  above.elevation_deg = 90;
  ViewOptions oblique;
  oblique.azimuth_deg = 35;
  oblique.elevation_deg = 25;
  const Case cases[] = {
      {{1, 1, 1}, {0, 0, 0}, {}},
      {{1, 1, 1}, {-20, 7, 3}, oblique},
      // Anisotropic voxels make an ellipsoid: seen along y its outline has semi-axes
      // radius * spacing.x and radius * spacing.z; seen from above, x and y.
      {{0.8f, 1.1f, 1.5f}, {5, 5, 5}, {}},
      {{0.8f, 1.1f, 1.5f}, {5, 5, 5}, above},
  };
  for (const Case& test_case : cases) {
    sim::ScanOptions scan = sim::default_scan_options(SampleType::u8);
    for (int axis = 0; axis < 3; ++axis) {
      scan.spacing[axis] = test_case.spacing[axis];
      scan.origin[axis] = test_case.origin[axis];
    }
    const Picture picture = render(sphere, scan, test_case.view, true);
    const std::string where = "spacing " + std::to_string(test_case.spacing.x) + " view " +
                              std::to_string(test_case.view.azimuth_deg) + "/" +
                              std::to_string(test_case.view.elevation_deg);
    const glm::vec2 scale = pixels_per_unit(picture.camera);
    ASSERT_NEAR(scale.x, scale.y, 1e-3f * scale.x) << "fit_camera: the same scale on both axes";
    const glm::vec3 s = test_case.spacing;
    const double semi_a = radius * s.x;
    const double semi_b = radius * (test_case.view.elevation_deg == 90 ? s.y : s.z);
    // The surface runs through the midpoints between inner and outer voxels: on average it
    // encloses the inner voxels' cubes, whose volume is the ball's, so its outline's
    // area-equivalent radius is the sphere's (measured within 0.4 pixel at 3 .. 4 pixels per
    // voxel).
    const double expected_radius = std::sqrt(semi_a * semi_b) * scale.x;
    EXPECT_GT(expected_radius, 30.0) << where;  // large enough for 1 pixel to mean something
    EXPECT_NEAR(std::sqrt(static_cast<double>(covered(picture)) / kPi), expected_radius, 1.0)
        << where;

    // The silhouette's centroid is where the sphere's centre projects.
    const glm::vec3 world_centre = test_case.origin + s * glm::vec3(c.x, c.y, c.z);
    const glm::vec3 centre = project(picture.camera, world_centre);
    double sum_x = 0, sum_y = 0;
    const std::uint32_t w = picture.camera.width;
    for (std::size_t i = 0; i < picture.depths.size(); ++i)
      if (std::isfinite(picture.depths[i])) {
        sum_x += i % w + 0.5;
        sum_y += i / w + 0.5;
      }
    EXPECT_NEAR(sum_x / covered(picture), centre.x, 0.25) << where;
    EXPECT_NEAR(sum_y / covered(picture), centre.y, 0.25) << where;

    // The near side shows: in the middle the depth is that of the sphere's point nearest the
    // viewer, to within a voxel, not of the far side (drawn if front faces were culled).
    const glm::vec3 towards_viewer = glm::transpose(picture.camera.world_to_view)[2];
    const glm::vec3 extent = static_cast<float>(radius) * s;
    const float near_depth = project(picture.camera, world_centre + towards_viewer * extent).z;
    const float far_depth = project(picture.camera, world_centre - towards_viewer * extent).z;
    const float voxel_depth = (far_depth - near_depth) / (2 * static_cast<float>(radius));
    const std::size_t middle = pixel_index(picture, centre);
    EXPECT_NEAR(picture.depths[middle], near_depth, voxel_depth) << where;
    // Facing the viewer there: lit almost fully (ambient + diffuse + specular = 1 when the
    // normal points exactly at the viewer; gradient normals of a binary sphere are within a
    // few degrees of it).
    EXPECT_GE(picture.pixels[middle], 235) << where;
  }
}

TEST(RenderSink, ReadingFramesWhileThePictureGrowsChangesNothing) {
  const sim::Grid grid{41, 37, 33};
  const sim::Sphere sphere(grid, {18, 19, 15}, 12.5);
  const sim::ScanOptions scan = sim::default_scan_options(SampleType::u8);
  ViewOptions view;
  view.azimuth_deg = -30;
  view.elevation_deg = 15;
  // Every frame copied and compared with the one before: the picture only grows (pixels are
  // added, depths only come nearer) as slices arrive.
  std::vector<std::uint8_t> previous_pixels;
  std::vector<float> previous_depths;
  std::size_t frames_that_grew = 0, depths_that_receded = 0, previous_covered = 0;
  const Picture inspected = render(sphere, scan, view, true, [&](const ZBufferRenderer& renderer) {
    const std::size_t n = std::size_t{renderer.width()} * renderer.height();
    std::vector<std::uint8_t> pixels(renderer.pixels(), renderer.pixels() + n);
    std::vector<float> depths(renderer.depths(), renderer.depths() + n);
    std::size_t now_covered = 0;
    for (std::size_t i = 0; i < n; ++i) {
      now_covered += std::isfinite(depths[i]);
      if (!previous_depths.empty()) depths_that_receded += depths[i] > previous_depths[i];
    }
    frames_that_grew += now_covered > previous_covered;
    previous_covered = now_covered;
    previous_pixels = std::move(pixels);
    previous_depths = std::move(depths);
  });
  const Picture untouched = render(sphere, scan, view, true);
  EXPECT_EQ(inspected.frames, grid.depth);  // one frame per slice the engine took
  EXPECT_EQ(depths_that_receded, 0u);
  EXPECT_GT(frames_that_grew, 20u);
  EXPECT_EQ(previous_pixels, inspected.pixels);  // the last frame is the picture
  EXPECT_EQ(inspected.pixels, untouched.pixels);
  EXPECT_EQ(0, std::memcmp(inspected.depths.data(), untouched.depths.data(),
                           inspected.depths.size() * sizeof(float)));
  EXPECT_GT(covered(untouched), 5000u);
}

TEST(RenderSink, FlatAndSmoothShadingCoverTheSamePixelsAtTheSameDepths) {
  const sim::Grid grid{33, 29, 25};
  const sim::Sphere sphere(grid, {16, 14, 12}, 10);
  const sim::ScanOptions scan = sim::default_scan_options(SampleType::u8);
  const Picture smooth = render(sphere, scan, {}, true);
  const Picture flat = render(sphere, scan, {}, false);
  EXPECT_EQ(0, std::memcmp(smooth.depths.data(), flat.depths.data(),
                           smooth.depths.size() * sizeof(float)));
  EXPECT_NE(smooth.pixels, flat.pixels);  // but the shading differs
  // Gradient normals vary smoothly; flat facets jump from polygon to polygon. Summed over
  // horizontally adjacent covered pixels, smooth shading changes less.
  auto roughness = [](const Picture& picture) {
    std::uint64_t sum = 0;
    const std::uint32_t w = picture.camera.width;
    for (std::size_t i = 0; i + 1 < picture.pixels.size(); ++i)
      if ((i + 1) % w != 0 && std::isfinite(picture.depths[i]) &&
          std::isfinite(picture.depths[i + 1]))
        sum += std::abs(picture.pixels[i] - picture.pixels[i + 1]);
    return sum;
  };
  EXPECT_LT(roughness(smooth), roughness(flat));
}

}  // namespace
}  // namespace mvox
