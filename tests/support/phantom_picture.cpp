#include "phantom_picture.h"

#include <gtest/gtest.h>

#include "mvox/engine.h"
#include "mvox/render_sink.h"
#include "mvox/slice_window.h"
#include "mvox/vertex_normals.h"
#include "phantom_factory.h"
#include "simulated_scanner.h"
#include "mvox/stream_volume.h"
#include "mvox/workspace_buffer.h"

namespace mvox::test {

PhantomPicture render_phantom(const std::string& name, const sim::Grid& grid,
                              const PhantomPictureSetup& setup) {
  const auto phantom = sim::make_phantom(name, grid, 1);
  sim::ScanOptions scan = sim::default_scan_options(SampleType::u8);
  scan.partial_volume = setup.partial_volume;
  sim::SimulatedScanner scanner(*phantom, scan);
  const VolumeInfo& info = scanner.info();
  const double threshold = sim::sample_threshold(sim::default_density_threshold(name), scan);

  PhantomPicture picture;
  glm::vec3 box_min, box_max;
  volume_bounds(info, &box_min, &box_max);
  picture.camera = fit_camera(box_min, box_max, setup.view, setup.width, setup.height);
  WorkspaceBuffer image_memory(zbuffer_workspace_bytes(setup.width, setup.height));
  ZBufferRenderer renderer;
  EXPECT_EQ(renderer.init(image_memory.data(), image_memory.bytes(), picture.camera,
                                setup.lighting), Status::ok);

  WorkspaceBuffer window_memory(slice_window_bytes(info.width, info.height, info.type));
  SliceWindow window;
  EXPECT_EQ(
      window.init(window_memory.data(), window_memory.bytes(), info.width, info.height, info.type),
      Status::ok);
  const VertexNormals normals(window, glm::vec3(1.0f));
  RenderSink sink(renderer, glm::vec3(1.0f), glm::vec3(0.0f), setup.smooth ? &normals : nullptr);

  EngineOptions options;
  options.polygon_geometry = true;
  WorkspaceBuffer engine_memory(engine_workspace_bytes(info.width, info.height, options));
  Engine engine;
  EXPECT_EQ(engine.init(engine_memory.data(), engine_memory.bytes(), info.width, info.height,
                        threshold, options, &sink),
            Status::ok);
  auto after_slice = [&](std::uint32_t slices_done) { setup.after_slice(slices_done, renderer); };
  const SliceProgress progress = setup.after_slice ? SliceProgress::of(after_slice) : SliceProgress{};
  EXPECT_EQ(stream_volume(scanner, engine, progress, &window), Status::ok);

  picture.width = renderer.width();
  picture.height = renderer.height();
  const std::size_t count = std::size_t{picture.width} * picture.height;
  picture.pixels.assign(renderer.pixels(), renderer.pixels() + count);
  picture.depths.assign(renderer.depths(), renderer.depths() + count);
  picture.counters = renderer.counters();
  return picture;
}

}  // namespace mvox::test
