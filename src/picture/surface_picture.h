#pragma once
// The picture side of an extraction job: a z-buffer renderer fitted to the volume, fed by the
// engine as layers complete, with frames written every N slices, an optional live window, and
// the final image committed together with the job's other outputs.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mvox/camera.h"
#include "mvox/render_sink.h"
#include "mvox/slice_source.h"
#include "mvox/zbuffer_renderer.h"
#include "write/output_file.h"

namespace mvox {

class LiveWindow;
class PictureLayer;

struct PictureOptions {
  std::string image_path;  // the final picture (.png, .pgm, .tif...); empty: none
  bool sync = false;       // make the picture durable before it appears (--sync)
  std::uint32_t width = 512;
  std::uint32_t height = 512;
  ViewOptions view;
  Lighting lighting;
  std::string frames_dir;  // a picture after every `every` slices; empty: none
  std::uint32_t every = 10;
  bool show = false;   // a live window, when there is a display
  bool smooth = true;  // gradient normals; false: each polygon shaded flat

  bool wanted() const { return !image_path.empty() || !frames_dir.empty() || show; }
};

// The name of the frame written after `slices_done` of `depth` slices: "frame_0010.png",
// zero-padded to at least 4 digits and to as many as `depth` has, so that names sort in order.
std::string frame_file_name(std::uint32_t slices_done, std::uint32_t depth);

class SurfacePicture {
 public:
  // Sets up the renderer for `volume` placed with `spacing` and `origin` (as the mesh is
  // written), drawing in the frame of the volume's box (picture_frame.h), so that the picture
  // does not depend on the box's size or place. `normals` (borrowed, may be null) gives smooth
  // shading. Creates the image's temporary file and the frames directory now, so that a bad path
  // fails before a long run. Throws mvox::Error.
  SurfacePicture(const VolumeInfo& volume, const std::array<double, 3>& spacing,
                 const std::array<double, 3>& origin, const VertexNormals* normals,
                 const PictureOptions& options);
  ~SurfacePicture();
  SurfacePicture(const SurfacePicture&) = delete;
  SurfacePicture& operator=(const SurfacePicture&) = delete;

  PolygonSink& sink() { return *sink_; }

  // After each slice the engine has taken: writes a frame every `every` slices and refreshes
  // the live window. Throws mvox::Error if a frame cannot be written.
  void after_slice(std::uint32_t slices_done);
  // False when after_slice() does nothing (no frames, no window), so need not be called; a
  // slab-parallel run then needs no SlabPictureFollower either.
  bool follows_slices() const { return writes_frames() || shows_window(); }
  bool writes_frames() const { return !options_.frames_dir.empty(); }
  bool shows_window() const { return live_window_ != nullptr; }
  // Seconds after_slice() has spent writing frames and updating the window: rendering time.
  double seconds_following() const { return seconds_following_; }

  // After the volume (of `slices` slices) is finished: the last frame, the window's final
  // picture, and the image encoded and sealed (OutputFile::seal). publish() then makes it appear.
  void complete(std::uint32_t slices);
  void publish();

  const ZBufferRenderer& renderer() const { return renderer_; }

  // Slab-parallel pictures (sort-last compositing): each worker draws its slabs into a layer of
  // its own, with its own slice window's `normals` (may be null), and the layers composited into
  // this picture give the picture one engine draws, bit for bit (ZBufferRenderer::composite).
  std::unique_ptr<PictureLayer> new_layer(const VertexNormals* normals) const;
  void composite(const PictureLayer& layer);
  // Frames and the window of a slab-parallel run (slab_picture_follower.h), which composites the
  // layers as they grow. take_frames_due() gives the frames due after `slices_done` slices
  // (every multiple of `every` since the last frame given, but not the last frame, which
  // complete() writes) and counts them as written from then on; the caller writes each to
  // frame_path(), which any thread may call. show_in_window() shows `pixels` (a copy) in the
  // live window, if there is one.
  std::vector<std::uint32_t> take_frames_due(std::uint32_t slices_done);
  std::string frame_path(std::uint32_t slices_done) const;
  void show_in_window(const std::uint8_t* pixels);
  void add_seconds_following(double seconds) { seconds_following_ += seconds; }
  // Forgets every layer composited so far, for the final compositing of a run whose frames
  // composited the layers as they grew: compositing adds the layers' counters.
  void start_over() { renderer_.clear(); }
  // A layer's arrays (width * height entries each) from another process (mvox-mpi).
  void composite(const float* depths, const std::uint8_t* shades, const std::uint32_t* tags);
  bool smooth() const { return options_.smooth; }
  // The picture's file, once complete() has sealed it (null without --image).
  OutputFile* image_file() { return image_file_ ? &*image_file_ : nullptr; }

 private:
  void write_frame(std::uint32_t slices_done);
  void start_tagging();  // before the first layer is composited

  PictureOptions options_;
  std::uint32_t depth_ = 0;    // slices the source announced: sets the frame names' width
  std::vector<float> memory_;  // the renderer's workspace: float-aligned
  ZBufferRenderer renderer_;
  std::vector<std::uint32_t> tags_;  // once layers are composited into it
  Camera camera_;
  glm::vec3 frame_spacing_{1.0f};  // the voxel size and origin in the picture's frame
  glm::vec3 frame_origin_{0.0f};
  std::optional<RenderSink> sink_;
  std::optional<OutputFile> image_file_;
  std::unique_ptr<LiveWindow> live_window_;
  std::uint32_t last_frame_ = 0;
  double seconds_following_ = 0;
};

}  // namespace mvox
