#include "pipeline/slab_picture_follower.h"

#include <algorithm>
#include <cstring>
#include <exception>

#include "picture/live_window.h"
#include "picture/surface_picture.h"
#include "pipeline/blocking_queue.h"
#include "write/slice_image_writer.h"

namespace mvox {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The renderer's picture as a slice view, its pixels read from `pixels` (a copy of them).
SliceView view_of(const std::vector<std::uint8_t>& pixels, const ZBufferRenderer& renderer) {
  SliceView view = renderer.picture();
  view.samples = pixels.data();
  return view;
}

}  // namespace

SlabPictureFollower::SlabPictureFollower(SurfacePicture& picture, std::uint32_t slabs,
                                         std::uint32_t slab_slices, std::uint32_t depth,
                                         unsigned workers, const Cancellation& cancellation)
    : picture_(picture),
      slab_slices_(slab_slices),
      depth_(depth),
      cancellation_(cancellation),
      drawn_(slabs, false),
      seconds_(workers, 0.0) {
  const std::size_t pixels = std::size_t{picture.renderer().width()} * picture.renderer().height();
  if (picture.writes_frames()) frame_copies_.assign(workers, std::vector<std::uint8_t>(pixels));
  if (picture.shows_window()) window_copy_.resize(pixels);
}

void SlabPictureFollower::slab_drawn(unsigned worker, std::uint32_t slab,
                                     const PictureLayer& layer) {
  const auto start = Clock::now();
  std::vector<std::uint32_t> due;
  std::uint64_t ticket = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    picture_.composite(layer);
    drawn_[slab] = true;
    const std::uint32_t before = first_undrawn_;
    while (first_undrawn_ < drawn_.size() && drawn_[first_undrawn_]) ++first_undrawn_;
    if (first_undrawn_ > before && !frame_copies_.empty()) {
      // The slices of the slabs drawn from the first one: one engine would have taken them all.
      due = picture_.take_frames_due(static_cast<std::uint32_t>(
          std::min<std::uint64_t>(depth_, std::uint64_t{first_undrawn_} * slab_slices_)));
      if (!due.empty()) {
        std::memcpy(frame_copies_[worker].data(), picture_.renderer().pixels(),
                    frame_copies_[worker].size());
        ticket = next_ticket_++;
      }
    }
  }
  if (!due.empty()) write_in_turn(worker, due, ticket);
  seconds_[worker] += seconds_since(start);
}

void SlabPictureFollower::write_in_turn(unsigned worker, const std::vector<std::uint32_t>& frames,
                                        std::uint64_t ticket) {
  std::exception_ptr failure;
  std::vector<std::vector<unsigned char>> encoded;
  try {
    const SliceView picture = view_of(frame_copies_[worker], picture_.renderer());
    for (const std::uint32_t frame : frames)
      encoded.push_back(encode_slice_image(picture_.frame_path(frame), picture));
  } catch (...) {
    failure = std::current_exception();
  }
  std::unique_lock<std::mutex> lock(turn_mutex_);
  turn_changed_.wait(lock, [&] { return writing_turn_ == ticket; });
  try {
    for (std::size_t i = 0; i < encoded.size() && !failure; ++i) {
      // A failed run writes no more: neither after a frame that failed (before the run is
      // cancelled, which happens only once the error reaches the run) nor after another error.
      if (frame_failed_ || cancellation_.cancelled()) break;
      write_image_file(picture_.frame_path(frames[i]), encoded[i]);
    }
  } catch (...) {
    failure = std::current_exception();
  }
  if (failure) frame_failed_ = true;
  ++writing_turn_;
  lock.unlock();
  turn_changed_.notify_all();
  if (failure) std::rethrow_exception(failure);
}

void SlabPictureFollower::show() {
  if (window_copy_.empty()) return;
  const auto start = Clock::now();
  // The window would skip an update this soon after the last one: so is the copy.
  if (start - last_shown_ < LiveWindow::kMinUpdateInterval) return;
  last_shown_ = start;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::memcpy(window_copy_.data(), picture_.renderer().pixels(), window_copy_.size());
  }
  picture_.show_in_window(window_copy_.data());
  window_seconds_ += seconds_since(start);
}

void SlabPictureFollower::finish() {
  picture_.start_over();
  for (const double seconds : seconds_) picture_.add_seconds_following(seconds);
  picture_.add_seconds_following(window_seconds_);
}

}  // namespace mvox
