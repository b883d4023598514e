// A program of another project that uses mvox's core, as a library user would: one inner voxel
// in a 5x4x3 volume, streamed slice by slice, must give the octahedron around it, 6 vertices and
// 8 triangles (one per octant; nothing to merge). Exit status 0 when it does.
#include <mvox/counting_sink.h>
#include <mvox/engine.h>
#include <mvox/stream_volume.h>
#include <mvox/workspace_buffer.h>

#include <cstdint>
#include <cstdio>

namespace {

// A volume held in memory, one slice at a time.
class OneVoxel final : public mvox::SliceSource {
 public:
  OneVoxel() {
    info_.width = 5;
    info_.height = 4;
    info_.depth = 3;
  }
  const mvox::VolumeInfo& info() const override { return info_; }
  bool next_slice(mvox::SliceView* slice) override {
    if (z_ == info_.depth) return false;
    for (std::uint8_t& sample : samples_) sample = 0;
    if (z_ == 1) samples_[1 * 5 + 2] = 200;  // voxel (2, 1, 1)
    slice->samples = samples_;
    slice->width = 5;
    slice->height = 4;
    slice->row_stride_bytes = 5;
    slice->type = mvox::SampleType::u8;
    ++z_;
    return true;
  }

 private:
  mvox::VolumeInfo info_;
  std::uint8_t samples_[20] = {};
  std::uint32_t z_ = 0;
};

}  // namespace

int main() {
  OneVoxel volume;
  mvox::CountingSink sink;
  const mvox::EngineOptions options;
  mvox::WorkspaceBuffer workspace(mvox::engine_workspace_bytes(5, 4, options));
  mvox::Engine engine;
  if (engine.init(workspace.data(), workspace.bytes(), 5, 4, 100, options, &sink) !=
          mvox::Status::ok ||
      mvox::stream_volume(volume, engine) != mvox::Status::ok)
    return 1;
  std::printf("%llu vertices, %llu polygons\n", static_cast<unsigned long long>(sink.vertices),
              static_cast<unsigned long long>(sink.polygons));
  return sink.vertices == 6 && sink.polygons == 8 ? 0 : 1;
}
