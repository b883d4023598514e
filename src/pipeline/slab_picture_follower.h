#pragma once
// Frames and the live window of a slab-parallel run (--frames, --show with --threads): the
// picture grows as the workers finish their slabs.
//
// One engine draws the picture slice by slice, so a frame after z slices shows the surface of
// the slices below z. Slab workers each draw into a layer of their own, composited into the
// picture only at the end (slab_extraction.h). To show the picture growing meanwhile, each
// worker composites its layer into the picture whenever it has drawn a slab, and the worker
// that completes the run of drawn slabs from the first one writes the frames due for the slices
// those slabs cover, from a copy of the picture taken under the lock. It encodes them while the
// others go on (encoding takes about a millisecond a frame at 512x512), and writes them once
// every frame before them is written, so that frames appear in order, as one engine's do, and
// none appears after one that failed. A frame so shows at least the slices below its number,
// as one engine's frame of that name does, and also the slabs that workers had drawn ahead by
// then: with a mesh, as many as a worker's recorded output holds while it waits for its turn to
// write (a slab or more each, up to most_chunks_per_worker); with a picture alone, any number.
// The frames grow slab by slab and are not one engine's byte for byte. The last frame
// and the picture are: the picture is cleared and the finished layers composited again
// (SurfacePicture::start_over). The live window is shown on the calling thread, which opened
// it, from a copy of its own.
//
// A frame that cannot be written fails the run like any error of a worker (slab_run_failure.h;
// should a later slice also be bad, that reading error may be the one reported, where one engine
// would have stopped at the frame). Once the run is cancelled no more frames are written.
//
// Memory: with frames, a copy of the picture's pixels per worker; with a live window, one more.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <vector>

namespace mvox {

class Cancellation;
class PictureLayer;
class SurfacePicture;

class SlabPictureFollower {
 public:
  // `slabs` slabs of `slab_slices` slices cutting a volume of `depth` slices, drawn by `workers`;
  // no frame is written once `cancellation` is cancelled.
  SlabPictureFollower(SurfacePicture& picture, std::uint32_t slabs, std::uint32_t slab_slices,
                      std::uint32_t depth, unsigned workers, const Cancellation& cancellation);
  SlabPictureFollower(const SlabPictureFollower&) = delete;
  SlabPictureFollower& operator=(const SlabPictureFollower&) = delete;

  // Worker `worker`, once it has drawn slab `slab` into `layer` (its own, which only it draws
  // into): composites the layer as it is into the picture, and writes the frames now due.
  // Throws mvox::Error if a frame cannot be written.
  void slab_drawn(unsigned worker, std::uint32_t slab, const PictureLayer& layer);
  // The calling thread: the live window, if there is one, shows the picture so far (at most as
  // often as the window repaints).
  void show();
  // Once the workers have stopped, before the finished layers are composited: clears the
  // picture of what the frames needed, and counts the time spent compositing, writing frames and
  // showing the window as the picture's (SurfacePicture::seconds_following).
  void finish();

 private:
  // Encodes `frames` from worker `worker`'s copy, then writes them when `ticket`'s turn comes.
  // The turn always passes on, also when this throws.
  void write_in_turn(unsigned worker, const std::vector<std::uint32_t>& frames,
                     std::uint64_t ticket);

  SurfacePicture& picture_;
  std::uint32_t slab_slices_;
  std::uint32_t depth_;
  const Cancellation& cancellation_;
  std::mutex mutex_;                 // guards the picture, drawn_ and first_undrawn_
  std::vector<bool> drawn_;          // per slab
  std::uint32_t first_undrawn_ = 0;  // slabs below it are all drawn
  // Per worker: with frames, the picture's pixels the frames it writes show; the time it spent
  // compositing and writing frames.
  std::vector<std::vector<std::uint8_t>> frame_copies_;
  std::vector<double> seconds_;
  // Frames are handed out in batches numbered in order (under mutex_), and written in that order.
  std::uint64_t next_ticket_ = 0;
  std::mutex turn_mutex_;  // guards writing_turn_ and frame_failed_; never taken with mutex_ held
  std::condition_variable turn_changed_;
  std::uint64_t writing_turn_ = 0;
  bool frame_failed_ = false;
  // The calling thread's: with a live window, what it shows; when it last did; its time.
  std::vector<std::uint8_t> window_copy_;
  std::chrono::steady_clock::time_point last_shown_{};
  double window_seconds_ = 0;
};

}  // namespace mvox
