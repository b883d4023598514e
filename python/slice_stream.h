#pragma once
// mvox.Extractor: slices pushed one at a time, the mesh returned as it completes.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "mvox/engine.h"
#include "mvox/workspace_buffer.h"
#include "picture/normal_window.h"
#include "write/mesh/mesh_arrays.h"

namespace mvox {
namespace py = pybind11;

// Memory: the engine's workspace (a function of width and height), with normals the last four
// slices, and one layer's output, whatever the number of slices.
//
// With normals, each slice is copied into a window of the last four and the engine takes the
// one before it (as stream_volume does for the command line): a vertex's normal needs the
// samples on both sides of its slice. So the mesh comes out one slice later than without.
class Extractor {
 public:
  Extractor(std::uint32_t width, std::uint32_t height, double threshold,
            std::array<double, 3> spacing, std::array<double, 3> origin, const std::string& method,
            bool triangulate, bool normals, bool interpolate);

  // What the slice completed: (vertices, polygon_offsets, polygon_indices), and the vertices'
  // normals fourth with normals=True. Indices count from the volume's first vertex, offsets
  // from the piece's first index.
  py::tuple push(py::array slice);
  // Ends the volume; returns the rest, as push() does.
  py::tuple finish();
  py::dict counters();

 private:
  void check(Status status);
  // Feeds `slice` to the engine, through the window when there are normals.
  Status take(const SliceView& slice);
  // What the writer holds so far, handed out and forgotten.
  py::tuple piece();

  std::uint32_t width_, height_;
  bool triangulate_;
  bool finished_ = false;
  bool busy_ = false;                      // a call is running (InUse)
  std::optional<SampleType> type_;         // of the first slice: the window keeps that type
  std::unique_ptr<NormalWindow> normals_;  // with normals=True
  std::unique_ptr<MeshArraysWriter> writer_;
  std::unique_ptr<WorkspaceBuffer> workspace_;
  Engine engine_;
};

}  // namespace mvox
