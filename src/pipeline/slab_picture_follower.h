#pragma once
// Frames and the live window of a slab-parallel run (--frames, --show with --threads): the
// picture grows as the workers finish their slabs.
//
// One engine draws the picture slice by slice, so a frame after z slices shows the surface of
// the slices below z. Slab workers each draw into a layer of their own, composited into the
// picture only at the end (slab_extraction.h). To show the picture growing meanwhile, each
// worker composites its layer into the picture whenever it has drawn a slab, and the worker
// that completes the run of drawn slabs from the first one writes the frames due for the slices
// those slabs cover, from a copy of the picture taken under the lock (encoding a frame takes
// about a millisecond at 512x512, which the other workers need not wait for). A frame so shows
// at least the slices below its number, and the slabs that workers had drawn ahead by then (a
// worker runs at most a few slabs ahead of the lowest one not yet written): the frames grow as
// one engine's do, in steps of a slab, but are not one engine's byte for byte. The last frame
// and the picture are: the picture is cleared and the finished layers composited again
// (SurfacePicture::start_over). The live window is shown on the calling thread, which opened
// it, from a copy of its own.
//
// Memory: with frames, a copy of the picture's pixels per worker; with a live window, one more.
#include <cstdint>
#include <mutex>
#include <vector>

namespace mvox {

class PictureLayer;
class SurfacePicture;

class SlabPictureFollower {
 public:
  // Slabs of `slab_slices` slices cutting a volume of `depth` slices, drawn by `workers`.
  SlabPictureFollower(SurfacePicture& picture, std::uint32_t slab_slices, std::uint32_t depth,
                      unsigned workers);
  SlabPictureFollower(const SlabPictureFollower&) = delete;
  SlabPictureFollower& operator=(const SlabPictureFollower&) = delete;

  // Worker `worker`, once it has drawn slab `slab` into `layer` (its own, which only it draws
  // into): composites the layer as it is into the picture, and writes the frames now due.
  // Throws mvox::Error if a frame cannot be written.
  void slab_drawn(unsigned worker, std::uint32_t slab, const PictureLayer& layer);
  // The calling thread: the live window, if there is one, shows the picture so far.
  void show();
  // Once the workers have stopped, before the finished layers are composited: clears the
  // picture of what the frames needed, and counts the time the frames took as the picture's.
  void finish();

 private:
  SurfacePicture& picture_;
  std::uint32_t slab_slices_;
  std::uint32_t depth_;
  std::mutex mutex_;                 // guards the picture, drawn_ and first_undrawn_
  std::vector<bool> drawn_;          // per slab
  std::uint32_t first_undrawn_ = 0;  // slabs below it are all drawn
  // Per worker, with frames: the picture's pixels the frames it writes show, and the time it
  // spent writing them.
  std::vector<std::vector<std::uint8_t>> frame_copies_;
  std::vector<double> frame_seconds_;
  std::vector<std::uint8_t> window_copy_;  // with a live window: what it shows
};

}  // namespace mvox
