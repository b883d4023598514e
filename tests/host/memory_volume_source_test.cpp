// MemoryVolumeSource: a volume in memory streamed without a copy, and read from anywhere, so that
// slab workers each stream their own slab of it (RangeReadable) instead of one thread handing
// slices out, with the same mesh as one engine.
#include "read/memory/memory_volume_source.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "slab_run_checks.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_extraction.h"
#include "write/mesh/ply_writer.h"

namespace mvox {
namespace {

VolumeInfo noise_info() {
  VolumeInfo info;
  info.width = 19;
  info.height = 13;
  info.depth = 41;
  info.type = SampleType::u8;
  return info;
}

std::vector<std::uint8_t> noise(const VolumeInfo& info) {
  return test::noise_samples(std::size_t{info.width} * info.height * info.depth, 7);
}

TEST(MemoryVolumeSource, ARangeStreamsExactlyItsSlicesWithoutACopy) {
  const VolumeInfo info = noise_info();
  const auto samples = noise(info);
  const std::ptrdiff_t slice_bytes = std::ptrdiff_t{info.width} * info.height;
  MemoryVolumeSource whole(samples.data(), info, slice_bytes, info.width);
  const RangeReadable* ranges = own_range_reader(whole);
  ASSERT_NE(ranges, nullptr) << "slab workers would wait on one thread handing slices out";
  auto range = ranges->open_range(10, 17);
  EXPECT_EQ(range->info().depth, info.depth);
  SliceView slice;
  for (std::uint32_t z = 10; z < 17; ++z) {
    ASSERT_TRUE(range->next_slice(&slice)) << z;
    EXPECT_EQ(slice.samples, samples.data() + z * slice_bytes) << z;
  }
  EXPECT_FALSE(range->next_slice(&slice));
  // The whole source is untouched by its ranges.
  ASSERT_TRUE(whole.next_slice(&slice));
  EXPECT_EQ(slice.samples, samples.data());
}

TEST(MemoryVolumeSource, SlabWorkersReadingTheirOwnSlabsWriteOneEnginesMesh) {
  const VolumeInfo info = noise_info();
  const auto samples = noise(info);
  const std::ptrdiff_t slice_bytes = std::ptrdiff_t{info.width} * info.height;
  test::ScratchDirectory dir;
  {
    MemoryVolumeSource source(samples.data(), info, slice_bytes, info.width);
    PlyWriter writer(dir.file("one.ply"));
    run_pipeline(source, 128, EngineOptions(), writer, "noise");
    writer.finish();
  }
  for (const unsigned threads : {2u, 3u}) {
    MemoryVolumeSource source(samples.data(), info, slice_bytes, info.width);
    PlyWriter writer(dir.file("slabs.ply"));
    SlabOptions slabs;
    slabs.threads = threads;
    slabs.slab_slices = 4;
    run_slab_pipeline(source, 128, EngineOptions(), &writer, slabs, "noise");
    writer.finish();
    EXPECT_TRUE(test::read_bytes(dir.file("slabs.ply")) == test::read_bytes(dir.file("one.ply")))
        << threads << " workers";
  }
}

}  // namespace
}  // namespace mvox
