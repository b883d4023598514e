#pragma once
// Marching cubes' vertex placement: where the samples, interpolated linearly along a voxel
// edge, cross the threshold (Lorensen and Cline). The engine keeps the samples of the two
// slices of the current cube layer for it. Marching voxels' vertices sit at midpoints unless
// EngineOptions::interpolate moves them here too: its vertices lie on the same voxel edges.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "mvox/mesh.h"
#include "mvox/slice.h"
#include "sample_load.h"

namespace mvox {

// One slice's samples, copied in their own type and packed (row stride = width * sample size).
struct SampleSlab {
  unsigned char* bytes = nullptr;  // width * height * 4 bytes of workspace: room for any type
  SampleType type = SampleType::u8;
  bool present = false;  // false for the all-outer slices before and after the volume
};

class EdgeInterpolation {
 public:
  // Bytes of workspace one slab needs: the widest sample type.
  static constexpr std::size_t slab_bytes(std::uint32_t width, std::uint32_t height) {
    return std::size_t{width} * height * sample_bytes(SampleType::f32);
  }

  // `margin`: how close to either voxel centre a vertex may come, in voxels. Marching voxels
  // keeps 0.01: a vertex on a voxel centre (a sample equal to the threshold) would have three
  // whole coordinates, and its polygon could then not be split into triangles without one in a
  // cube face (polygon_triangulation.h). 0.01 stays a fraction even next to 26,700, the largest
  // slice side, where floats are 1/256 apart. Marching cubes emits triangles: 0.
  void init(unsigned char* slab0, unsigned char* slab1, std::uint32_t width, std::uint32_t height,
            double threshold, float margin = 0.0f) {
    slabs_[0] = {slab0, SampleType::u8, false};
    slabs_[1] = {slab1, SampleType::u8, false};
    width_ = width;
    height_ = height;
    threshold_ = static_cast<float>(threshold);
    margin_ = margin;
  }

  // Keeps the samples of slice z in slot z & 1.
  void store(int slot, const SliceView& slice) {
    SampleSlab& slab = slabs_[slot];
    const std::size_t row_bytes = std::size_t{width_} * sample_bytes(slice.type);
    const auto* source = static_cast<const unsigned char*>(slice.samples);
    for (std::uint32_t y = 0; y < height_; ++y)
      std::memcpy(slab.bytes + y * row_bytes, source + y * slice.row_stride_bytes, row_bytes);
    slab.type = slice.type;
    slab.present = true;
  }

  // Slot `slot` now stands for a slice outside the volume.
  void clear(int slot) { slabs_[slot].present = false; }

  // Moves `vertex`, which sits at the midpoint of its voxel pair, to where the interpolated
  // samples cross the threshold. A pair with a voxel outside the volume keeps the midpoint:
  // there is no sample to interpolate, and the surface closes half a voxel outside, as marching
  // voxels closes it. The crossing stays on the pair's segment even for NaN samples.
  void place(Vertex& vertex) const {
    if (const SampleType* type = common_type())
      dispatch_sample_type(
          *type, [&](auto tag) { place_as<static_cast<int>(decltype(tag)::value)>(vertex); });
    else
      place_as<kMixedTypes>(vertex);
  }

  // The type of every slice kept (null when the two differ): a layer can then be compiled for
  // it, with no dispatch per vertex.
  const SampleType* common_type() const {
    if (!slabs_[0].present) return &slabs_[1].type;
    if (!slabs_[1].present || slabs_[0].type == slabs_[1].type) return &slabs_[0].type;
    return nullptr;
  }

  // place() for slices of type kType (kMixedTypes: each slab's own type, dispatched per sample).
  template <int kType>
  void place_as(Vertex& vertex) const {
    const int axis = static_cast<int>(vertex.axis);
    float& along = along_axis(vertex);
    const float lower = along - 0.5f;  // exact: midpoints are whole numbers plus a half
    if (lower < 0.0f) return;
    const auto x = static_cast<std::uint32_t>(axis == 0 ? lower : vertex.x);
    const auto y = static_cast<std::uint32_t>(axis == 1 ? lower : vertex.y);
    const auto z = static_cast<std::uint32_t>(axis == 2 ? lower : vertex.z);
    const std::uint32_t x1 = x + (axis == 0), y1 = y + (axis == 1), z1 = z + (axis == 2);
    if (x1 >= width_ || y1 >= height_) return;
    const SampleSlab& slab0 = slabs_[z & 1];
    const SampleSlab& slab1 = slabs_[z1 & 1];
    if (!slab0.present || !slab1.present) return;
    const float a = sample<kType>(slab0, x, y), b = sample<kType>(slab1, x1, y1);
    const float t = (threshold_ - a) / (b - a);
    along =
        lower + (t >= 0.0f && t <= 1.0f ? std::min(std::max(t, margin_), 1.0f - margin_) : 0.5f);
  }

  static constexpr int kMixedTypes = -1;

 private:
  template <int kType>
  float sample(const SampleSlab& slab, std::uint32_t x, std::uint32_t y) const {
    if constexpr (kType == kMixedTypes) {
      return dispatch_sample_type(slab.type, [&](auto tag) {
        return sample<static_cast<int>(decltype(tag)::value)>(slab, x, y);
      });
    } else {
      constexpr auto type = static_cast<SampleType>(kType);
      const std::size_t row_bytes = std::size_t{width_} * sample_bytes(type);
      return load_sample<type>(slab.bytes + y * row_bytes, x);
    }
  }

  SampleSlab slabs_[2];
  std::uint32_t width_ = 0, height_ = 0;
  float threshold_ = 0;
  float margin_ = 0;
};

}  // namespace mvox
