#pragma once
// Reading overlapped with extraction: a SliceSource that reads (decodes) slice k + 1 on a
// thread of its own while the caller works on slice k. Decoding PNG or TIFF slices can take as
// long as extracting and rendering them, so on a machine with a second core the reading mostly
// disappears from the run's time. Memory: two more slices, fixed.
//
// The inner source is only ever called from the reading thread. Whatever it throws is rethrown
// by next_slice() at the slice where it happened, so errors read exactly as without prefetching.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "mvox/slice_source.h"

namespace mvox {

class PrefetchingSource final : public SliceSource {
 public:
  // `inner` is borrowed and must outlive this object; reading starts at once.
  explicit PrefetchingSource(SliceSource& inner);
  ~PrefetchingSource() override;  // stops the reading thread, even mid-volume
  PrefetchingSource(const PrefetchingSource&) = delete;
  PrefetchingSource& operator=(const PrefetchingSource&) = delete;

  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override;

  // The memory this adds to its inner source's for a volume of `info`: its two slice buffers.
  static std::uint64_t buffer_bytes(const VolumeInfo& info);

 private:
  // One slice's samples, rows packed; filled by the reader, then handed to the caller.
  struct Buffer {
    std::vector<unsigned char> bytes;
    SliceView view;       // the slice as the inner source gave it, samples in `bytes`
    bool filled = false;  // holds a slice the caller has not finished with
  };

  void read_ahead();  // the reading thread

  SliceSource& inner_;
  const VolumeInfo info_;
  Buffer buffers_[2];
  std::mutex mutex_;
  std::condition_variable changed_;
  int next_to_read_ = 0;                   // the buffer the reader fills next
  int next_to_hand_out_ = 0;               // the buffer the caller gets next
  int held_ = -1;                          // the buffer the caller's last view points into, or -1
  bool finished_ = false;                  // the inner source has no more slices (or failed)
  bool stopping_ = false;                  // the destructor wants the reader to stop
  bool reader_done_ = false;               // the reading thread has returned
  std::atomic<bool> cancel_reads_{false};  // read_cancellation.h: give up a blocked read
  std::exception_ptr error_;  // what the inner source threw, for the slice after the last good
  std::thread reader_;
};

}  // namespace mvox
