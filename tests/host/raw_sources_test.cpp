// Raw slices and raw volumes (src/read/raw/raw_slices_source.h, raw_volume_source.h): every
// sample type in either byte order gives the native values, files of the wrong size are refused
// (also when they change after opening), many small slices are read a chunk at a time in fixed
// memory, a pipe is read as it arrives; and the CThead slices of ../shared/datasets when present.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "file_io.h"
#include "read/input_files.h"
#include "read/input_format.h"
#include "read/raw/raw_format.h"
#include "read/raw/raw_slices_source.h"
#include "read/raw/raw_volume_source.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::encode_f32;
using test::encode_i16;
using test::encode_u16;
using test::error_of;
using test::read_all;
using test::read_through;
using test::ScratchDirectory;
using test::write_bytes;

std::string file_name(const std::string& path) { return fs::path(path).filename().string(); }

constexpr int kRawWidth = 5;
constexpr int kRawHeight = 3;
constexpr int kRawSamples = kRawWidth * kRawHeight;

// u16 sample i of slice k: spans values above 255 and above 32767.
std::uint16_t raw_u16(int k, int i) {
  return static_cast<std::uint16_t>(40000 + k * 1000 + i * 1711);
}
std::int16_t raw_i16(int k, int i) { return static_cast<std::int16_t>(-20000 + k * 7 + i * 2500); }
float raw_f32(int k, int i) { return (i % 2 ? -1.0f : 1.0f) * (0.1f + k) * std::pow(10.0f, i - 7); }

template <typename T>
std::vector<T> raw_slice(T (*sample)(int, int), int k) {
  std::vector<T> slice(kRawSamples);
  for (int i = 0; i < kRawSamples; ++i) slice[i] = sample(k, i);
  return slice;
}

// Writes slices s1, s2, s10 (k = 0, 1, 2) in scrambled order and reads them through the factory.
template <typename T>
void expect_raw_slices(const std::string& spec, T (*sample)(int, int),
                       std::vector<unsigned char> (*encode)(const std::vector<T>&, ByteOrder),
                       ByteOrder order, SampleType type) {
  ScratchDirectory dir;
  const char* names[] = {"s1", "s2", "s10"};
  for (int k : {2, 0, 1}) write_bytes(dir / names[k], encode(raw_slice(sample, k), order));
  std::unique_ptr<SliceSource> source = open_slice_source({dir.str()}, parse_raw_format(spec));
  ASSERT_NE(dynamic_cast<RawSlicesSource*>(source.get()), nullptr);
  EXPECT_EQ(source->info().width, static_cast<std::uint32_t>(kRawWidth));
  EXPECT_EQ(source->info().height, static_cast<std::uint32_t>(kRawHeight));
  EXPECT_EQ(source->info().depth, 3u);
  EXPECT_EQ(source->info().type, type);
  const auto slices = read_all<T>(*source);
  ASSERT_EQ(slices.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(slices[k], raw_slice(sample, k)) << "slice " << k;
}

TEST(RawSlices, U16BigAndLittleEndianGiveNativeValues) {
  expect_raw_slices<std::uint16_t>("5x3:u16be", raw_u16, encode_u16, ByteOrder::big,
                                   SampleType::u16);
  expect_raw_slices<std::uint16_t>("5x3:u16le", raw_u16, encode_u16, ByteOrder::little,
                                   SampleType::u16);
}

TEST(RawSlices, I16KeepsNegativeValues) {
  expect_raw_slices<std::int16_t>("5x3:i16be", raw_i16, encode_i16, ByteOrder::big,
                                  SampleType::i16);
  expect_raw_slices<std::int16_t>("5x3:i16le", raw_i16, encode_i16, ByteOrder::little,
                                  SampleType::i16);
}

TEST(RawSlices, F32LittleEndianGivesNativeValues) {
  expect_raw_slices<float>("5x3:f32le", raw_f32, encode_f32, ByteOrder::little, SampleType::f32);
}

TEST(RawSlices, ByteOrderMatters) {
  // Big-endian data read as little-endian gives each value with its bytes swapped; this shows the
  // order in the spec is honoured rather than ignored.
  ScratchDirectory dir;
  write_bytes(dir / "s1", encode_u16(raw_slice(raw_u16, 0), ByteOrder::big));
  std::unique_ptr<SliceSource> source =
      open_slice_source({dir / "s1"}, parse_raw_format("5x3:u16le"));
  const auto slices = read_all<std::uint16_t>(*source);
  ASSERT_EQ(slices.size(), 1u);
  for (int i = 0; i < kRawSamples; ++i) {
    const std::uint16_t v = raw_u16(0, i);
    EXPECT_EQ(slices[0][i], static_cast<std::uint16_t>((v >> 8) | (v << 8)));
  }
}

TEST(RawSlices, RefusesFileOfWrongSize) {
  ScratchDirectory dir;
  write_bytes(dir / "CThead.1", encode_u16(raw_slice(raw_u16, 0), ByteOrder::big));
  std::vector<unsigned char> long_slice = encode_u16(raw_slice(raw_u16, 1), ByteOrder::big);
  long_slice.push_back(0);
  write_bytes(dir / "CThead.2", long_slice);
  write_bytes(dir / "CThead.3", encode_u16(raw_slice(raw_u16, 2), ByteOrder::big));
  const std::string message =
      error_of([&] { read_through({dir / "CThead.*"}, parse_raw_format("5x3:u16be")); });
  EXPECT_CONTAINS(message, dir / "CThead.2: file is 31 bytes, expected 30");

  // A file that changes size after the source opened is caught when its slice is read.
  fs::resize_file(dir / "CThead.2", 30);
  RawSlicesSource source(list_input_files({dir.str()}, InputKind::raw_files),
                         parse_raw_format("5x3:u16be"));
  fs::resize_file(dir / "CThead.3", 29);
  SliceView view;
  EXPECT_TRUE(source.next_slice(&view));
  EXPECT_TRUE(source.next_slice(&view));
  EXPECT_CONTAINS(error_of([&] { source.next_slice(&view); }), dir / "CThead.3: file is 29 bytes");
}

TEST(RawVolume, ReadsSliceBySliceEqualToTheWrittenData) {
  ScratchDirectory dir;
  constexpr int kDepth = 6;
  std::vector<std::uint16_t> all;
  for (int k = 0; k < kDepth; ++k) {
    const std::vector<std::uint16_t> slice = raw_slice(raw_u16, k);
    all.insert(all.end(), slice.begin(), slice.end());
  }
  write_bytes(dir / "volume_5x3x6_u16be.raw", encode_u16(all, ByteOrder::big));
  std::unique_ptr<SliceSource> source =
      open_slice_source({dir / "volume_5x3x6_u16be.raw"}, parse_raw_format("5x3x6:u16be"));
  ASSERT_NE(dynamic_cast<RawVolumeSource*>(source.get()), nullptr);
  EXPECT_EQ(source->info().width, static_cast<std::uint32_t>(kRawWidth));
  EXPECT_EQ(source->info().height, static_cast<std::uint32_t>(kRawHeight));
  EXPECT_EQ(source->info().depth, static_cast<std::uint32_t>(kDepth));
  EXPECT_EQ(source->info().type, SampleType::u16);
  const auto slices = read_all<std::uint16_t>(*source);
  ASSERT_EQ(slices.size(), static_cast<std::size_t>(kDepth));
  for (int k = 0; k < kDepth; ++k) EXPECT_EQ(slices[k], raw_slice(raw_u16, k)) << "slice " << k;
}

TEST(RawVolume, ReadsU8AndF32Volumes) {
  ScratchDirectory dir;
  std::vector<unsigned char> bytes(7 * 5 * 4);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 3);
  write_bytes(dir / "engine.raw", bytes);
  RawVolumeSource u8_source(dir / "engine.raw", parse_raw_format("7x5x4:u8"));
  const auto u8_slices = read_all<std::uint8_t>(u8_source);
  ASSERT_EQ(u8_slices.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_TRUE(std::equal(u8_slices[k].begin(), u8_slices[k].end(), bytes.begin() + k * 35));
  }

  std::vector<float> all;
  for (int k = 0; k < 2; ++k) {
    const std::vector<float> slice = raw_slice(raw_f32, k);
    all.insert(all.end(), slice.begin(), slice.end());
  }
  write_bytes(dir / "f.raw", encode_f32(all, ByteOrder::little));
  RawVolumeSource f32_source(dir / "f.raw", parse_raw_format("5x3x2:f32le"));
  const auto f32_slices = read_all<float>(f32_source);
  ASSERT_EQ(f32_slices.size(), 2u);
  EXPECT_EQ(f32_slices[1], raw_slice(raw_f32, 1));
}

TEST(RawVolume, RefusesFileOfWrongSizeAndWrongInputs) {
  ScratchDirectory dir;
  write_bytes(dir / "short.raw", std::vector<unsigned char>(7 * 5 * 4 - 1));
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "short.raw"}, parse_raw_format("7x5x4:u8")); }),
      dir / "short.raw: file is 139 bytes, expected 140");
  write_bytes(dir / "long.raw", std::vector<unsigned char>(7 * 5 * 4 * 2 + 2));
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "long.raw"}, parse_raw_format("7x5x4:u16le")); }),
      dir / "long.raw: file is 282 bytes, expected 280");

  write_bytes(dir / "ok.raw", std::vector<unsigned char>(140));
  EXPECT_CONTAINS(error_of([&] {
                    read_through({dir / "ok.raw", dir / "short.raw"}, parse_raw_format("7x5x4:u8"));
                  }),
                  "one volume file");
  EXPECT_CONTAINS(error_of([&] { read_through({dir.str()}, parse_raw_format("7x5x4:u8")); }),
                  dir.str() + ": is a directory");
  EXPECT_CONTAINS(error_of([&] { read_through({dir / "*.raw"}, parse_raw_format("7x5x4:u8")); }),
                  dir / "*.raw: matches 3 files");
  EXPECT_CONTAINS(
      error_of([&] { read_through({dir / "absent.raw"}, parse_raw_format("7x5x4:u8")); }),
      dir / "absent.raw");
  // A glob that matches exactly one file is fine.
  EXPECT_NO_THROW(read_through({dir / "o*.raw"}, parse_raw_format("7x5x4:u8")));
}

// A volume of many small slices: they are read a chunk of several at a time (one read per
// slice cost more than extracting a slice of a few voxels), each swapped to native order as it
// is handed out, and the chunk is the memory the source says it holds.
std::vector<std::uint16_t> many_slices_u16(int depth) {
  std::vector<std::uint16_t> all;
  for (int k = 0; k < depth; ++k) {
    const std::vector<std::uint16_t> slice = raw_slice(raw_u16, k);
    all.insert(all.end(), slice.begin(), slice.end());
  }
  return all;
}

TEST(RawVolume, ManySmallSlicesAreReadAChunkAtATimeInFixedMemory) {
  ScratchDirectory dir;
  constexpr int kDepth = 5000;  // 30-byte slices: 2184 to a 64 KiB chunk, so three chunks
  write_bytes(dir / "v.raw", encode_u16(many_slices_u16(kDepth), ByteOrder::big));
  RawVolumeSource source(dir / "v.raw", parse_raw_format("5x3x5000:u16be"));
  EXPECT_EQ(source.working_bytes(), (RawVolumeSource::kChunkBytes / 30) * 30);
  const auto slices = read_all<std::uint16_t>(source);
  ASSERT_EQ(slices.size(), static_cast<std::size_t>(kDepth));
  for (int k = 0; k < kDepth; ++k) ASSERT_EQ(slices[k], raw_slice(raw_u16, k)) << "slice " << k;

  // A slice larger than a chunk is read alone, in a buffer of its own size.
  const std::size_t big = RawVolumeSource::kChunkBytes + 7;
  write_bytes(dir / "big.raw", std::vector<unsigned char>(2 * big, 9));
  RawVolumeSource big_source(dir / "big.raw", parse_raw_format(std::to_string(big) + "x1x2:u8"));
  EXPECT_EQ(big_source.working_bytes(), big);
  EXPECT_EQ(read_all<std::uint8_t>(big_source).size(), 2u);
}

// The kernel copies file data into memory that is not 64-byte aligned several times slower
// (src/read/read_buffer.h), so a slice read alone, in a volume file or in a file of its own,
// must start on a page.
bool on_a_page(const void* pointer) {
  return reinterpret_cast<std::uintptr_t>(pointer) % 4096 == 0;
}

TEST(RawVolume, SlicesReadAloneStartOnAPage) {
  ScratchDirectory dir;
  const std::size_t slice_bytes = RawVolumeSource::kChunkBytes + 5;  // one slice a read
  write_bytes(dir / "v.raw", std::vector<unsigned char>(3 * slice_bytes, 1));
  RawVolumeSource volume(dir / "v.raw", parse_raw_format(std::to_string(slice_bytes) + "x1x3:u8"));
  SliceView slice;
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(volume.next_slice(&slice));
    EXPECT_TRUE(on_a_page(slice.samples)) << "volume slice " << k << " at " << slice.samples;
  }
  write_bytes(dir / "s0.raw", std::vector<unsigned char>(100, 1));
  write_bytes(dir / "s1.raw", std::vector<unsigned char>(100, 2));
  RawSlicesSource files({dir / "s0.raw", dir / "s1.raw"}, parse_raw_format("10x10:u8"));
  for (int k = 0; k < 2; ++k) {
    ASSERT_TRUE(files.next_slice(&slice));
    EXPECT_TRUE(on_a_page(slice.samples)) << "slice file " << k << " at " << slice.samples;
  }
}

// Writes `bytes` into the FIFO at `path` in pieces of odd sizes with pauses between, so that
// reads end inside slices, then closes it.
void trickle_into_fifo(const std::string& path, const std::vector<unsigned char>& bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0) << path;
  const std::size_t pieces[] = {1, 7, 29, 100, 3, 64};
  std::size_t done = 0;
  for (int i = 0; done < bytes.size(); ++i) {
    const std::size_t piece = std::min(pieces[i % 6], bytes.size() - done);
    ASSERT_EQ(::write(fd, bytes.data() + done, piece), static_cast<ssize_t>(piece));
    done += piece;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ::close(fd);
}

TEST(RawVolume, APipeIsReadAsItArrivesWhereverItsPiecesEnd) {
  ScratchDirectory dir;
  ASSERT_EQ(::mkfifo((dir / "v.raw").c_str(), 0600), 0);
  constexpr int kDepth = 200;
  std::thread writer([&] {
    trickle_into_fifo(dir / "v.raw", encode_u16(many_slices_u16(kDepth), ByteOrder::big));
  });
  {
    RawVolumeSource source(dir / "v.raw", parse_raw_format("5x3x200:u16be"));
    const auto slices = read_all<std::uint16_t>(source);
    ASSERT_EQ(slices.size(), static_cast<std::size_t>(kDepth));
    for (int k = 0; k < kDepth; ++k) EXPECT_EQ(slices[k], raw_slice(raw_u16, k)) << "slice " << k;
  }
  writer.join();
}

TEST(RawVolume, APipeThatEndsInsideASliceFailsAtThatSlice) {
  ScratchDirectory dir;
  ASSERT_EQ(::mkfifo((dir / "v.raw").c_str(), 0600), 0);
  // Two slices of 35 bytes and ten bytes of the third.
  std::thread writer([&] { trickle_into_fifo(dir / "v.raw", std::vector<unsigned char>(80, 1)); });
  {
    RawVolumeSource source(dir / "v.raw", parse_raw_format("7x5x4:u8"));
    SliceView view;
    EXPECT_TRUE(source.next_slice(&view));
    EXPECT_TRUE(source.next_slice(&view));
    EXPECT_CONTAINS(error_of([&] { source.next_slice(&view); }),
                    dir / "v.raw: ended after 80 bytes, expected 140 for a 7x5x4 u8 volume");
  }
  writer.join();
}

// ---------------------------------------------------------------------------------------------
// Real data, when ../shared/datasets is present (never in the repository).

// Each slab worker opens the volume again by its path (a reader of its own, for the kernel's
// read-ahead). Replaced meanwhile, by another file or by a FIFO, the path is refused: with two
// threads a run mixed slabs of two files, or waited in open() for the FIFO's writer for ever.
TEST(RawVolume, ARangeOfAVolumeReplacedSinceItWasOpenedIsRefused) {
  ScratchDirectory dir;
  const RawFormat format = parse_raw_format("7x5x4:u8");
  write_bytes(dir / "v.raw", std::string(140, '\x10'));
  write_bytes(dir / "other.raw", std::string(140, '\x20'));
  RawVolumeSource source(dir / "v.raw", format);
  auto range_reads = [&] {
    std::unique_ptr<SliceSource> range = source.open_range(2, 4);
    SliceView view;
    range->next_slice(&view);
  };
  EXPECT_NO_THROW(range_reads());  // the same file: read as before
  fs::rename(dir / "other.raw", dir / "v.raw");
  EXPECT_CONTAINS(error_of(range_reads),
                  dir / "v.raw: was replaced by another file while mvox read it");
  fs::remove(dir / "v.raw");
  ASSERT_EQ(::mkfifo((dir / "v.raw").c_str(), 0600), 0);
  EXPECT_CONTAINS(error_of(range_reads),
                  dir / "v.raw: was replaced by another file while mvox read it");
}

TEST(SharedDatasets, CtheadReadsAsU16BigEndian) {
  const std::string folder = std::string(MVOX_SHARED_DATASETS) + "/cthead";
  if (!fs::is_directory(folder)) GTEST_SKIP() << folder << " is absent (optional real data)";

  const std::string pattern = folder + "/CThead.*";
  const std::vector<std::string> files = list_input_files({pattern}, InputKind::raw_files);
  ASSERT_EQ(files.size(), 113u);
  for (std::size_t k = 0; k < files.size(); ++k) {
    ASSERT_EQ(file_name(files[k]), "CThead." + std::to_string(k + 1));
  }

  std::unique_ptr<SliceSource> source =
      open_slice_source({pattern}, parse_raw_format("256x256:u16be"));
  EXPECT_EQ(source->info().width, 256u);
  EXPECT_EQ(source->info().height, 256u);
  EXPECT_EQ(source->info().depth, 113u);
  EXPECT_EQ(source->info().type, SampleType::u16);
  // Figures from cthead/INFO.txt (computed there with numpy, >u2).
  std::uint16_t min_value = 65535;
  std::uint16_t max_value = 0;
  double sum = 0;
  std::uint32_t slice_count = 0;
  SliceView view;
  while (source->next_slice(&view)) {
    ++slice_count;
    for (std::uint32_t y = 0; y < view.height; ++y) {
      const auto* row = reinterpret_cast<const std::uint16_t*>(
          static_cast<const char*>(view.samples) + y * view.row_stride_bytes);
      for (std::uint32_t x = 0; x < view.width; ++x) {
        min_value = std::min(min_value, row[x]);
        max_value = std::max(max_value, row[x]);
        sum += row[x];
      }
    }
  }
  EXPECT_EQ(slice_count, 113u);
  EXPECT_EQ(min_value, 0);
  EXPECT_EQ(max_value, 3272);
  EXPECT_NEAR(sum / (256.0 * 256.0 * 113.0), 379.542, 0.001);
}

}  // namespace
}  // namespace mvox
