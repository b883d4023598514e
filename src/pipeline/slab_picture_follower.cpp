#include "pipeline/slab_picture_follower.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "picture/surface_picture.h"

namespace mvox {
namespace {

SliceView view_of(const std::vector<std::uint8_t>& pixels, const ZBufferRenderer& renderer) {
  SliceView view;
  view.samples = pixels.data();
  view.width = renderer.width();
  view.height = renderer.height();
  view.row_stride_bytes = renderer.width();
  view.type = SampleType::u8;
  return view;
}

}  // namespace

SlabPictureFollower::SlabPictureFollower(SurfacePicture& picture, std::uint32_t slab_slices,
                                         std::uint32_t depth, unsigned workers)
    : picture_(picture),
      slab_slices_(slab_slices),
      depth_(depth),
      drawn_((depth + slab_slices - 1) / slab_slices, false),
      frame_seconds_(workers, 0.0) {
  const std::size_t pixels = std::size_t{picture.renderer().width()} * picture.renderer().height();
  if (picture.writes_frames()) frame_copies_.assign(workers, std::vector<std::uint8_t>(pixels));
  if (picture.shows_window()) window_copy_.resize(pixels);
}

void SlabPictureFollower::slab_drawn(unsigned worker, std::uint32_t slab,
                                     const PictureLayer& layer) {
  std::vector<std::uint32_t> due;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    picture_.composite(layer);
    drawn_[slab] = true;
    const std::uint32_t before = first_undrawn_;
    while (first_undrawn_ < drawn_.size() && drawn_[first_undrawn_]) ++first_undrawn_;
    if (first_undrawn_ == before || frame_copies_.empty()) return;
    due = picture_.frames_due(static_cast<std::uint32_t>(
        std::min<std::uint64_t>(depth_, std::uint64_t{first_undrawn_} * slab_slices_)));
    if (due.empty()) return;
    std::memcpy(frame_copies_[worker].data(), picture_.renderer().pixels(),
                frame_copies_[worker].size());
  }
  const auto start = std::chrono::steady_clock::now();
  for (const std::uint32_t frame : due)
    picture_.write_frame_showing(frame, view_of(frame_copies_[worker], picture_.renderer()));
  frame_seconds_[worker] +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void SlabPictureFollower::show() {
  if (window_copy_.empty()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::memcpy(window_copy_.data(), picture_.renderer().pixels(), window_copy_.size());
  }
  picture_.show_in_window(window_copy_.data());
}

void SlabPictureFollower::finish() {
  picture_.start_over();
  for (const double seconds : frame_seconds_) picture_.add_seconds_following(seconds);
}

}  // namespace mvox
