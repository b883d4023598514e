#include "picture/surface_picture.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "error.h"
#include "message_line.h"
#include "picture/live_window.h"
#include "picture/picture_frame.h"
#include "picture/picture_layer.h"
#include "write/slice_image_writer.h"

namespace mvox {
namespace {

void prepare_frames_dir(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw Error(dir, "cannot create the frames directory: " + error.message());
  if (!std::filesystem::is_directory(dir, error))
    throw Error(dir, "frames directory is not a directory");
}

}  // namespace

std::string frame_file_name(std::uint32_t slices_done, std::uint32_t depth) {
  // Numbered by slices done, zero-padded so that names sort in order.
  int digits = 4;
  for (std::uint32_t d = depth; d >= 10000; d /= 10) ++digits;
  char name[32];
  std::snprintf(name, sizeof name, "frame_%0*u.png", digits, slices_done);
  return name;
}

SurfacePicture::SurfacePicture(const VolumeInfo& volume, const std::array<double, 3>& spacing,
                               const std::array<double, 3>& origin, const VertexNormals* normals,
                               const PictureOptions& options)
    : options_(options), depth_(volume.depth) {
  const std::size_t bytes = zbuffer_workspace_bytes(options.width, options.height);
  if (bytes == 0)
    throw Error("--image-size", "image size " + std::to_string(options.width) + "x" +
                                    std::to_string(options.height) + " is out of range (1.." +
                                    std::to_string(kMaxImageSide) + " per side)");
  if (options.every == 0) throw Error("--every", "must be at least 1");
  if (!options.image_path.empty()) check_image_extension(options.image_path);

  // The box the surface can occupy (voxel coordinates -0.5 .. n - 0.5, as volume_bounds()
  // gives it), in double, and the picture drawn in its frame (picture_frame.h says why).
  const double extent[3] = {double(volume.width), double(volume.height), double(volume.depth)};
  Vector3d low, high;
  for (int axis = 0; axis < 3; ++axis) {
    const double last = extent[axis] > 0 ? extent[axis] - 0.5 : 0.5;
    low[axis] = origin[axis] - 0.5 * spacing[axis];
    high[axis] = origin[axis] + last * spacing[axis];
  }
  const PictureFrame frame = PictureFrame::around(low, high);
  const Camera camera =
      fit_camera(frame.point(low), frame.point(high), options.view, options.width, options.height);
  memory_.resize((bytes + sizeof(float) - 1) / sizeof(float));
  const Status status =
      renderer_.init(memory_.data(), memory_.size() * sizeof(float), camera, options.lighting);
  if (status != Status::ok)
    throw Error("renderer", std::string("cannot start: ") + status_message(status));
  camera_ = camera;
  frame_spacing_ = frame.length(spacing);
  frame_origin_ = frame.point(origin);
  sink_.emplace(renderer_, frame_spacing_, frame_origin_, options.smooth ? normals : nullptr);

  if (!options.frames_dir.empty()) prepare_frames_dir(options.frames_dir);
  if (!options.image_path.empty()) image_file_.emplace(options.image_path, options.sync);
  if (options.show) {
    std::string why_not;
    live_window_ = LiveWindow::open("mvox", &why_not);
    // The window only shows the run: without it the run is still worth doing.
    if (!live_window_)
      print_message("warning", "--show: " + why_not + "; going on without a window");
  }
}

SurfacePicture::~SurfacePicture() = default;

std::unique_ptr<PictureLayer> SurfacePicture::new_layer(const VertexNormals* normals) const {
  return std::make_unique<PictureLayer>(camera_, options_.lighting, frame_spacing_, frame_origin_,
                                        options_.smooth ? normals : nullptr);
}

void SurfacePicture::start_tagging() {
  if (!tags_.empty()) return;
  tags_.resize(std::size_t{renderer_.width()} * renderer_.height());
  renderer_.tag_pixels(tags_.data());
}

void SurfacePicture::composite(const PictureLayer& layer) {
  start_tagging();
  if (renderer_.composite(layer.renderer()) != Status::ok)
    throw Error("renderer", "internal error: a layer of another size");
}

void SurfacePicture::composite(const float* depths, const std::uint8_t* shades,
                               const std::uint32_t* tags) {
  start_tagging();
  if (renderer_.composite(depths, shades, tags) != Status::ok)
    throw Error("renderer", "internal error: a layer without pixels");
}

std::vector<std::uint32_t> SurfacePicture::take_frames_due(std::uint32_t slices_done) {
  std::vector<std::uint32_t> due;
  if (options_.frames_dir.empty()) return due;
  const std::uint32_t every = options_.every;
  for (std::uint64_t frame = std::uint64_t{last_frame_ / every + 1} * every;
       frame <= slices_done && frame < depth_; frame += every)
    due.push_back(static_cast<std::uint32_t>(frame));
  if (!due.empty()) last_frame_ = due.back();
  return due;
}

std::string SurfacePicture::frame_path(std::uint32_t slices_done) const {
  return (std::filesystem::path(options_.frames_dir) / frame_file_name(slices_done, depth_))
      .string();
}

void SurfacePicture::show_in_window(const std::uint8_t* pixels) {
  if (live_window_) live_window_->show(pixels, renderer_.width(), renderer_.height());
}

void SurfacePicture::write_frame(std::uint32_t slices_done) {
  if (options_.frames_dir.empty()) return;
  write_slice_image(frame_path(slices_done), renderer_.picture());
  last_frame_ = slices_done;
}

void SurfacePicture::after_slice(std::uint32_t slices_done) {
  const bool frame = slices_done % options_.every == 0 && !options_.frames_dir.empty();
  if (!frame && !live_window_) return;
  const auto start = std::chrono::steady_clock::now();
  if (frame) write_frame(slices_done);
  if (live_window_) live_window_->show(renderer_.pixels(), renderer_.width(), renderer_.height());
  seconds_following_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void SurfacePicture::complete(std::uint32_t slices) {
  // The layer above the last slice (the top cap) is drawn by finish(), after the last
  // after_slice(): the last frame is always the complete picture.
  write_frame(slices);
  if (live_window_)
    live_window_->show(renderer_.pixels(), renderer_.width(), renderer_.height(), true);
  if (image_file_) {
    const std::vector<unsigned char> encoded =
        encode_slice_image(options_.image_path, renderer_.picture());
    image_file_->write(encoded.data(), encoded.size());
    image_file_->seal();
  }
}

void SurfacePicture::publish() {
  if (image_file_) image_file_->publish();
}

}  // namespace mvox
