#pragma once
// A phantom scanned, extracted and rendered in memory, the way `mvox demo --image` does it:
// for the renderer's tests (golden images, silhouettes, progressive frames).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mvox/camera.h"
#include "mvox/zbuffer_renderer.h"
#include "phantom.h"

namespace mvox::test {

struct PhantomPicture {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> pixels;  // row by row from the top
  std::vector<float> depths;         // per pixel, +infinity where nothing was drawn
  Camera camera;
  RenderCounters counters;
};

struct PhantomPictureSetup {
  std::uint32_t width = 128;
  std::uint32_t height = 128;
  ViewOptions view;
  Lighting lighting;
  bool partial_volume = true;  // scanned with partial-volume edges (smooth normals)
  bool smooth = true;          // gradient normals; false: flat
  // Called after every slice the engine takes, with the picture so far.
  std::function<void(std::uint32_t slices_done, const ZBufferRenderer&)> after_slice;
};

// `name` (sim::make_phantom, seed 1) on `grid`, scanned as u8 at its default threshold,
// streamed through the fast engine into a renderer fitted to the volume.
PhantomPicture render_phantom(const std::string& name, const sim::Grid& grid,
                              const PhantomPictureSetup& setup = {});

}  // namespace mvox::test
