// Reading overlapped with extraction: the prefetching source hands out exactly the inner
// source's slices, in batches bounded by bytes, never reads more than two batches ahead, hands a
// slow input over slice by slice, rethrows a reader's error at the slice where it happened, and
// stops cleanly when the caller gives up mid-volume.
#include "pipeline/prefetching_source.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "error.h"
#include "mesh_capture.h"
#include "phantom_factory.h"
#include "simulated_scanner.h"

namespace mvox {
namespace {

// Slices whose every sample says where it is, in rows padded to an odd stride, with a buffer the
// next call overwrites (as readers do); optionally fails at slice `fail_at`.
class PatternSource final : public SliceSource {
 public:
  PatternSource(std::uint32_t depth, std::int64_t fail_at = -1)
      : fail_at_(fail_at), buffer_(kStride * kHeight) {
    info_.width = kWidth;
    info_.height = kHeight;
    info_.depth = depth;
    info_.type = SampleType::u16;
  }
  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override {
    const std::thread::id me = std::this_thread::get_id();
    if (reader_ == std::thread::id()) reader_ = me;
    other_threads += reader_ != me;
    if (next_ == fail_at_) throw Error("slice_" + std::to_string(next_) + ".png", "truncated");
    if (next_ >= info_.depth) return false;
    for (std::uint32_t y = 0; y < kHeight; ++y)
      for (std::uint32_t x = 0; x < kWidth; ++x) {
        const std::uint16_t value = expected(x, y, next_);
        std::memcpy(buffer_.data() + y * kStride + 2 * x, &value, 2);
      }
    *slice = {buffer_.data(), kWidth, kHeight, kStride, SampleType::u16};
    ++next_;
    read = next_;
    return true;
  }
  static std::uint16_t expected(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return static_cast<std::uint16_t>(1000 * z + 37 * y + x);
  }

  static constexpr std::uint32_t kWidth = 9, kHeight = 7, kStride = 2 * 9 + 5;
  std::atomic<std::uint32_t> read{0};  // slices read so far
  std::atomic<int> other_threads{0};   // calls from a thread other than the first caller's

 private:
  VolumeInfo info_;
  std::int64_t fail_at_;
  std::vector<unsigned char> buffer_;
  std::uint32_t next_ = 0;
  std::thread::id reader_;
};

void expect_pattern(const SliceView& slice, std::uint32_t z) {
  ASSERT_EQ(slice.width, PatternSource::kWidth);
  ASSERT_EQ(slice.height, PatternSource::kHeight);
  ASSERT_EQ(slice.type, SampleType::u16);
  for (std::uint32_t y = 0; y < slice.height; ++y)
    for (std::uint32_t x = 0; x < slice.width; ++x) {
      std::uint16_t value;
      std::memcpy(
          &value,
          static_cast<const unsigned char*>(slice.samples) + y * slice.row_stride_bytes + 2 * x, 2);
      ASSERT_EQ(value, PatternSource::expected(x, y, z)) << x << "," << y << "," << z;
    }
}

constexpr std::size_t kPatternSliceBytes =
    std::size_t{PatternSource::kWidth} * PatternSource::kHeight * 2;

// Batch sizes to try: one slice per batch (as for slices of 64 KiB and more), three slices, and
// the default, which holds every small test volume whole.
const std::size_t kBatchBytes[] = {1, 3 * kPatternSliceBytes + 5,
                                   PrefetchingSource::kDefaultBatchBytes};

TEST(PrefetchingSource, HandsOutEverySliceInOrderAndReadsAtMostTwoBatchesAhead) {
  for (const std::size_t batch_bytes : kBatchBytes) {
    SCOPED_TRACE("batches of " + std::to_string(batch_bytes) + " bytes");
    const std::size_t per_batch =
        PrefetchingSource::slices_per_batch(batch_bytes, kPatternSliceBytes);
    PatternSource inner(40);
    PrefetchingSource prefetched(inner, batch_bytes);
    EXPECT_EQ(prefetched.info().depth, 40u);
    SliceView slice;
    std::uint32_t handed_out = 0;
    while (prefetched.next_slice(&slice)) {
      expect_pattern(slice, handed_out);
      // Give the reader time to run ahead as far as it may: the rest of the batch the caller
      // takes slices from, and one more batch. With one slice per batch: the one the caller
      // holds, and the next.
      std::this_thread::sleep_for(std::chrono::microseconds(300));
      ++handed_out;
      EXPECT_LE(inner.read.load(), handed_out + 2 * per_batch - 1)
          << "after slice " << handed_out - 1;
      // The view stays valid until the next call, however far the reader has got.
      expect_pattern(slice, handed_out - 1);
    }
    EXPECT_EQ(handed_out, 40u);
    EXPECT_FALSE(prefetched.next_slice(&slice));
    EXPECT_EQ(inner.other_threads.load(), 0) << "the inner source is called from one thread only";
  }
}

TEST(PrefetchingSource, BatchesAreBoundedByBytesNotBySlices) {
  EXPECT_EQ(PrefetchingSource::slices_per_batch(64 * 1024, 1), 64u * 1024);
  EXPECT_EQ(PrefetchingSource::slices_per_batch(64 * 1024, 4096), 16u);
  EXPECT_EQ(PrefetchingSource::slices_per_batch(64 * 1024, 5000), 13u);
  // A slice as large as a batch, or larger, crosses alone.
  EXPECT_EQ(PrefetchingSource::slices_per_batch(64 * 1024, 64 * 1024), 1u);
  EXPECT_EQ(PrefetchingSource::slices_per_batch(64 * 1024, 512 * 512 * 2), 1u);
}

// A source that says how much memory it holds, for working_bytes().
class SizedSource final : public SliceSource {
 public:
  SizedSource(std::uint32_t width, std::uint32_t height, SampleType type, std::uint64_t working)
      : working_(working) {
    info_.width = width;
    info_.height = height;
    info_.depth = 1;
    info_.type = type;
  }
  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView*) override { return false; }
  std::uint64_t working_bytes() const override { return working_; }

 private:
  VolumeInfo info_;
  std::uint64_t working_;
};

TEST(PrefetchingSource, WorkingBytesAreTheInnerSourcesAndTwoBatches) {
  {
    SizedSource one_byte_slices(1, 1, SampleType::u8, 1000);
    PrefetchingSource prefetched(one_byte_slices);
    EXPECT_EQ(prefetched.working_bytes(), 1000u + 2 * PrefetchingSource::kDefaultBatchBytes);
  }
  {
    SizedSource small_slices(30, 20, SampleType::u16, 1000);  // 1200 bytes, 54 to a batch
    PrefetchingSource prefetched(small_slices);
    EXPECT_EQ(prefetched.working_bytes(), 1000u + 2 * 54 * 1200);
  }
  {
    SizedSource large_slices(512, 512, SampleType::f32, 1000);  // 1 MiB: one to a batch
    PrefetchingSource prefetched(large_slices);
    EXPECT_EQ(prefetched.working_bytes(), 1000u + 2 * 1024 * 1024);
  }
  {
    SizedSource cannot_tell(1, 1, SampleType::u8, 0);
    PrefetchingSource prefetched(cannot_tell);
    EXPECT_EQ(prefetched.working_bytes(), 0u);
  }
}

// Slices whose size changes every few slices (a reader may hand out such slices; the engine
// refuses them, but only when it gets them): a batch holds slices of one shape.
class ShapeChangingSource final : public SliceSource {
 public:
  explicit ShapeChangingSource(std::uint32_t depth) {
    info_.width = width_of(0);
    info_.height = 2;
    info_.depth = depth;
    info_.type = SampleType::u8;
  }
  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override {
    if (next_ >= info_.depth) return false;
    const std::uint32_t width = width_of(next_);
    buffer_.assign(std::size_t{width} * 2, static_cast<unsigned char>(next_));
    *slice = {buffer_.data(), width, 2, width, SampleType::u8};
    ++next_;
    return true;
  }
  static std::uint32_t width_of(std::uint32_t z) { return 1 + (z / 3) % 4; }

 private:
  VolumeInfo info_;
  std::vector<unsigned char> buffer_;
  std::uint32_t next_ = 0;
};

TEST(PrefetchingSource, SlicesOfChangingShapeKeepTheirShapeAndOrder) {
  for (const std::size_t batch_bytes : {std::size_t{1}, std::size_t{10}, std::size_t{4096}}) {
    ShapeChangingSource inner(200);
    PrefetchingSource prefetched(inner, batch_bytes);
    SliceView slice;
    std::uint32_t z = 0;
    while (prefetched.next_slice(&slice)) {
      ASSERT_EQ(slice.width, ShapeChangingSource::width_of(z)) << z;
      ASSERT_EQ(slice.height, 2u);
      for (std::uint32_t y = 0; y < 2; ++y)
        for (std::uint32_t x = 0; x < slice.width; ++x)
          ASSERT_EQ(
              static_cast<const unsigned char*>(slice.samples)[y * slice.row_stride_bytes + x],
              static_cast<unsigned char>(z))
              << x << "," << y << "," << z;
      ++z;
    }
    EXPECT_EQ(z, 200u);
  }
}

// Gives `ready` slices at once, then waits (in next_slice, as a reader of a silent pipe waits in
// read()) until released, then gives the rest.
class TricklingSource final : public SliceSource {
 public:
  TricklingSource(std::uint32_t ready, std::uint32_t depth) : ready_(ready) {
    info_.width = 4;
    info_.height = 4;
    info_.depth = depth;
    info_.type = SampleType::u8;
  }
  const VolumeInfo& info() const override { return info_; }
  bool next_slice(SliceView* slice) override {
    if (next_ >= info_.depth) return false;
    if (next_ == ready_) {
      // The limit only keeps a broken prefetcher, one that waits for the rest of the input
      // before handing over the first slices, from hanging the test: it fails instead.
      std::unique_lock<std::mutex> lock(mutex_);
      if (!released_changed_.wait_for(lock, std::chrono::seconds(20), [&] { return released_; }))
        gave_up_ = true;
    }
    buffer_.fill(static_cast<unsigned char>(next_));
    *slice = {buffer_.data(), 4, 4, 4, SampleType::u8};
    ++next_;
    return true;
  }
  void release() {
    std::lock_guard<std::mutex> lock(mutex_);
    released_ = true;
    released_changed_.notify_all();
  }
  bool gave_up() {
    std::lock_guard<std::mutex> lock(mutex_);
    return gave_up_;
  }

 private:
  VolumeInfo info_;
  std::uint32_t ready_;
  std::array<unsigned char, 16> buffer_{};
  std::uint32_t next_ = 0;
  std::mutex mutex_;
  std::condition_variable released_changed_;
  bool released_ = false;
  bool gave_up_ = false;  // waited out the limit without a release
};

TEST(PrefetchingSource, ASlowInputReachesTheCallerAsItArrivesNotWhenABatchIsFull) {
  // Five slices of 16 bytes are far from filling a 64 KiB batch: they must still be handed over
  // while the source waits for more (a live scanner, a pipe that trickles, the FIFO of
  // bad_input_interrupts_test's AnErrorWhileTheInputPipeStaysOpenEndsTheRunAtOnce).
  TricklingSource inner(5, 8);
  PrefetchingSource prefetched(inner);
  SliceView slice;
  for (std::uint32_t z = 0; z < 5; ++z) {
    ASSERT_TRUE(prefetched.next_slice(&slice));
    EXPECT_EQ(static_cast<const unsigned char*>(slice.samples)[15], z);
  }
  EXPECT_FALSE(inner.gave_up()) << "the first slices waited for the rest of the input";
  const double waited_before = prefetched.seconds_waiting();
  // The caller now waits for slice 5 until the source is released: time spent reading.
  std::thread releaser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    inner.release();
  });
  for (std::uint32_t z = 5; z < 8; ++z) {
    ASSERT_TRUE(prefetched.next_slice(&slice));
    EXPECT_EQ(static_cast<const unsigned char*>(slice.samples)[0], z);
  }
  releaser.join();
  EXPECT_FALSE(prefetched.next_slice(&slice));
  EXPECT_GE(prefetched.seconds_waiting() - waited_before, 0.04);  // of the 50 ms
}

TEST(PrefetchingSource, AReadErrorIsRethrownAtTheSliceWhereItHappened) {
  for (const std::size_t batch_bytes : kBatchBytes) {
    SCOPED_TRACE("batches of " + std::to_string(batch_bytes) + " bytes");
    PatternSource inner(40, 13);
    PrefetchingSource prefetched(inner, batch_bytes);
    SliceView slice;
    for (std::uint32_t z = 0; z < 13; ++z) {
      ASSERT_TRUE(prefetched.next_slice(&slice));
      expect_pattern(slice, z);
    }
    for (int attempt = 0; attempt < 2; ++attempt) {
      try {
        prefetched.next_slice(&slice);
        ADD_FAILURE() << "no error";
      } catch (const Error& error) {
        EXPECT_STREQ(error.what(), "slice_13.png: truncated");  // the reader's own message
      }
    }
  }
}

TEST(PrefetchingSource, StopsCleanlyWhenTheCallerGivesUpMidVolume) {
  for (const std::size_t batch_bytes : kBatchBytes) {
    const std::size_t per_batch =
        PrefetchingSource::slices_per_batch(batch_bytes, kPatternSliceBytes);
    for (int slices_taken : {0, 1, 2, 5}) {
      PatternSource inner(100000);
      {
        PrefetchingSource prefetched(inner, batch_bytes);
        SliceView slice;
        for (int i = 0; i < slices_taken; ++i) ASSERT_TRUE(prefetched.next_slice(&slice));
      }  // joins the reader: must not hang, must not read on
      EXPECT_LE(inner.read.load(), static_cast<std::uint32_t>(slices_taken) + 2 * per_batch)
          << "batches of " << batch_bytes << " bytes, " << slices_taken << " slices taken";
    }
  }
}

// Through the engine: the same mesh with and without reading ahead.
TEST(PrefetchingSource, TheEngineSeesTheSameVolume) {
  const auto phantom = sim::make_phantom("blobs", {37, 29, 31}, 8);
  sim::SimulatedScanner direct(*phantom);
  sim::SimulatedScanner inner(*phantom);
  PrefetchingSource prefetched(inner);
  const double threshold = sim::sample_threshold(0.5, sim::default_scan_options(SampleType::u8));
  const test::Mesh expected = test::extract(direct, threshold);
  const test::Mesh actual = test::extract(prefetched, threshold);
  ASSERT_EQ(actual.vertices.size(), expected.vertices.size());
  for (std::size_t i = 0; i < actual.vertices.size(); ++i)
    ASSERT_TRUE(test::same_position(actual.vertices[i], expected.vertices[i])) << i;
  EXPECT_EQ(actual.polygons, expected.polygons);
  EXPECT_GT(actual.polygons.size(), 100u);
}

}  // namespace
}  // namespace mvox
