#pragma once
// Gradient normals for a streamed volume, ready to use: the slice window's memory, the window
// and the VertexNormals over it, owned together. Pass window() to the pipeline so the engine is
// fed behind it, and normals() to the mesh writer and the renderer.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mvox/slice_source.h"
#include "mvox/slice_window.h"
#include "mvox/vertex_normals.h"

namespace mvox {

class NormalWindow {
 public:
  // `spacing` is the voxel size the mesh is written with. Throws mvox::Error naming
  // `input_label` if the slices are too large to keep four of.
  // `depth`: the slices to hold (slice_window.h), more than four for a caller that asks about
  // vertices some layers after the engine made them.
  NormalWindow(const VolumeInfo& volume, const std::array<double, 3>& spacing,
               const std::string& input_label, std::uint32_t depth = kSliceWindowDepth);
  NormalWindow(const NormalWindow&) = delete;
  NormalWindow& operator=(const NormalWindow&) = delete;

  // Empties the window and starts it afresh for slices of `type`, no wider than the type it
  // was made for: for a caller that learns the type from the first slice (mvox.Extractor makes
  // it for f32, the widest).
  void restart_for(SampleType type);

  SliceWindow& window() { return window_; }
  const VertexNormals& normals() const { return normals_; }

 private:
  std::vector<unsigned char> memory_;
  std::uint32_t depth_;
  SliceWindow window_;
  VertexNormals normals_;
};

}  // namespace mvox
