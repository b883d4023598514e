// Reading overlapped with extraction: the prefetching source hands out exactly the inner
// source's slices, never reads more than two ahead, rethrows a reader's error at the slice where
// it happened, and stops cleanly when the caller gives up mid-volume.
#include "prefetching_source.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
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

TEST(PrefetchingSource, HandsOutEverySliceInOrderAndReadsAtMostTwoAhead) {
  PatternSource inner(40);
  PrefetchingSource prefetched(inner);
  EXPECT_EQ(prefetched.info().depth, 40u);
  SliceView slice;
  std::uint32_t handed_out = 0;
  while (prefetched.next_slice(&slice)) {
    expect_pattern(slice, handed_out);
    // Give the reader time to run ahead as far as it may: the slice the caller holds, and two.
    std::this_thread::sleep_for(std::chrono::microseconds(300));
    ++handed_out;
    EXPECT_LE(inner.read.load(), handed_out + 1) << "after slice " << handed_out - 1;
    // The view stays valid until the next call, however far the reader has got.
    expect_pattern(slice, handed_out - 1);
  }
  EXPECT_EQ(handed_out, 40u);
  EXPECT_FALSE(prefetched.next_slice(&slice));
  EXPECT_EQ(inner.other_threads.load(), 0) << "the inner source is called from one thread only";
}

TEST(PrefetchingSource, AReadErrorIsRethrownAtTheSliceWhereItHappened) {
  PatternSource inner(40, 13);
  PrefetchingSource prefetched(inner);
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

TEST(PrefetchingSource, StopsCleanlyWhenTheCallerGivesUpMidVolume) {
  for (int slices_taken : {0, 1, 2, 5}) {
    PatternSource inner(1000);
    {
      PrefetchingSource prefetched(inner);
      SliceView slice;
      for (int i = 0; i < slices_taken; ++i) ASSERT_TRUE(prefetched.next_slice(&slice));
    }  // joins the reader: must not hang, must not read on
    EXPECT_LE(inner.read.load(), static_cast<std::uint32_t>(slices_taken) + 2);
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
