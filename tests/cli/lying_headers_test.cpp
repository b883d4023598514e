// Headers that lie: a compressed or encoded file whose header declares far more data than its
// bytes can hold, or slices too large to extract at all, are refused from the header alone
// (compression_bounds.h, memory_plan.h), before anything of the declared size is allocated. Each
// case runs the real command line and checks the refusal (one line, nothing left on disk) and
// that the processes it ran stayed far below the declared size: under 200 MiB, where the
// declared data are gigabytes.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "command_runner.h"
#include "deflate.h"
#include "refusal.h"
#include "tiff_bytes.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::deflate_bytes;
using test::run_mvox;
using test::ScratchDirectory;

void write_file(const fs::path& path, const std::string& text,
                const std::vector<unsigned char>& bytes = {}) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

// The largest resident size of any process this test has run and waited for, in MiB.
double peak_child_mebibytes() {
  struct rusage usage {};
  getrusage(RUSAGE_CHILDREN, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

constexpr double kPeakLimitMebibytes = 200;

class LyingHeaders : public ::testing::Test {
 protected:
  void expect_refused(const std::string& arguments, const std::string& subject,
                      const std::string& problem) {
    test::expect_refused(dir_.path(), arguments + " -o mesh.ply --stats report.json -q", subject,
                         problem);
    EXPECT_LT(peak_child_mebibytes(), kPeakLimitMebibytes);
  }
  ScratchDirectory dir_;
};

const std::vector<unsigned char> kTenZeros(10, 0);

TEST_F(LyingHeaders, GzipNrrdDeclaringAFourGigabyteSlice) {
  write_file(dir_.path() / "big.nrrd",
             "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 65536 65536 1\nencoding: gzip\n\n",
             deflate_bytes(kTenZeros, true));
  expect_refused("extract big.nrrd -t 1", "big.nrrd",
                 "bytes of compressed data cannot hold the 4294967296 bytes of a 65536x65536x1 "
                 "u8 volume");
}

TEST_F(LyingHeaders, GzipNrrdOfThreeLargeSlicesWithAPicture) {
  write_file(dir_.path() / "big.nrrd",
             "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 30000 30000 3\nendian: little\n"
             "encoding: gzip\n\n",
             deflate_bytes(std::vector<unsigned char>(1000, 0), true));
  expect_refused("extract big.nrrd -t 1 --image picture.png", "big.nrrd",
                 "cannot hold the 5400000000 bytes");
}

TEST_F(LyingHeaders, ZlibMetaImageDeclaringGigabytes) {
  write_file(dir_.path() / "big.mha",
             "NDims = 3\nDimSize = 30000 30000 3\nElementType = MET_USHORT\n"
             "CompressedData = True\nElementDataFile = LOCAL\n",
             deflate_bytes(std::vector<unsigned char>(1000, 0), false));
  expect_refused("extract big.mha -t 1", "big.mha", "cannot hold the 5400000000 bytes");
}

// No lie here, but the size alone settles it: the engine cannot address such slices, which is
// known before the first of their 4 GiB is read (it took 4.2 GB and 18 s before).
TEST_F(LyingHeaders, SlicesTooLargeToExtractAreRefusedBeforeReading) {
  const fs::path data = dir_.path() / "huge.raw";
  { std::ofstream create(data, std::ios::binary); }
  fs::resize_file(data, std::uint64_t{65536} * 65536);  // sparse: no disk space taken
  expect_refused("extract huge.raw --raw 65536x65536x1:u8 -t 1", "huge.raw",
                 "slices of 65536x65536 voxels are too large to extract");
  write_file(dir_.path() / "huge.nhdr",
             "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 65536 65536 1\nencoding: raw\n"
             "data file: huge.raw\n");
  expect_refused("extract huge.nhdr -t 1", "huge.nhdr", "too large to extract");
}

TEST_F(LyingHeaders, PngDeclaringMoreThanOpenCvDecodes) {
  fs::create_directory(dir_.path() / "stack");
  write_file(dir_.path() / "stack/s0.png",
             test::png_file(65535, 65535, 8, deflate_bytes(kTenZeros, false)));
  expect_refused("extract stack -t 1", "stack/s0.png",
                 "image is 65535x65535, 4294836225 pixels: more than the 2^30 pixels");
}

TEST_F(LyingHeaders, PngWhoseDataCannotHoldItsImage) {
  fs::create_directory(dir_.path() / "stack");
  write_file(dir_.path() / "stack/s0.png",
             test::png_file(20000, 20000, 8, deflate_bytes(kTenZeros, false)));
  expect_refused("extract stack -t 1", "stack/s0.png",
                 "bytes of image data cannot hold a 20000x20000 image");
}

// A later slice is checked against the first from its header, before it is decoded.
TEST_F(LyingHeaders, ALaterSliceDeclaringAnotherSizeIsRefusedBeforeDecoding) {
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 12x10x8 -q", dir_.path()).exit_code, 0);
  write_file(dir_.path() / "stack/sphere_0005.png",
             test::png_file(30000, 30000, 8,
                            deflate_bytes(std::vector<unsigned char>(1 << 20, 0), false)));
  expect_refused("extract stack -t 128", "stack/sphere_0005.png",
                 "image is 30000x30000, expected 12x10 like the first slice");
}

// An honest PNG whose size exceeds the budget given: refused from its header, and --dry-run
// says what it would need.
TEST_F(LyingHeaders, APngLargerThanTheMemoryBudgetIsRefusedFromItsHeader) {
  constexpr std::uint32_t kSide = 8000;                                  // 64 MB of samples a slice
  std::vector<unsigned char> rows(std::size_t{kSide} * (kSide + 1), 0);  // filter byte + row
  fs::create_directory(dir_.path() / "stack");
  write_file(dir_.path() / "stack/s0.png",
             test::png_file(kSide, kSide, 8, deflate_bytes(rows, false)));
  expect_refused("extract stack -t 1 --max-memory 200M", "stack",
                 "over the --max-memory 200M budget of 200 MiB");
  const auto dry =
      run_mvox("extract stack -t 1 -o mesh.ply --max-memory 4G --dry-run", dir_.path());
  EXPECT_EQ(dry.exit_code, 0) << dry.output;
  EXPECT_NE(dry.output.find("8000x8000x1 u8 voxels"), std::string::npos) << dry.output;
  EXPECT_NE(dry.output.find("budget: 4.0 GiB (--max-memory 4G): fits"), std::string::npos)
      << dry.output;
  EXPECT_FALSE(fs::exists(dir_.path() / "mesh.ply"));
  EXPECT_LT(peak_child_mebibytes(), kPeakLimitMebibytes);
}

// The same for a TIFF page: a deflate strip of 64 MB of samples, honest, over the budget.
TEST_F(LyingHeaders, ATiffPageLargerThanTheMemoryBudgetIsRefusedFromItsDirectory) {
  constexpr std::uint32_t kSide = 8000;
  test::TiffPageBytes page;
  page.width = page.height = kSide;
  page.compression = 8;  // deflate
  page.chunks = {test::zlib_compressed(std::vector<unsigned char>(std::size_t{kSide} * kSide, 0))};
  const std::vector<unsigned char> file = test::tiff_file_bytes({page});
  write_file(dir_.path() / "page.tif", "", file);
  expect_refused("extract page.tif -t 1 --max-memory 200M", "page.tif",
                 "over the --max-memory 200M budget of 200 MiB");
}

// The gzip trailer records the data's size (modulo 2^32), and mvox takes a matching trailer at
// its word to avoid a second pass. A trailer that lies, either way, must neither let a short
// stream through nor stop a good one.
class GzipTrailer : public LyingHeaders {
 protected:
  void SetUp() override {
    for (std::size_t i = 0; i < volume_.size(); ++i)
      volume_[i] = static_cast<unsigned char>(i % 13 < 6 ? 200 : 10);
    write_nrrd("honest.nrrd", deflate_bytes(volume_, true));
    ASSERT_EQ(run_mvox("extract honest.nrrd -t 100 -o honest.ply -q", dir_.path()).exit_code, 0);
  }
  void write_nrrd(const std::string& name, const std::vector<unsigned char>& gzip) {
    write_file(dir_.path() / name,
               "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 13 11 9\nencoding: gzip\n\n", gzip);
  }
  static std::vector<unsigned char> with_trailer_size(std::vector<unsigned char> gzip,
                                                      std::uint32_t size) {
    for (int i = 0; i < 4; ++i)
      gzip[gzip.size() - 4 + i] = static_cast<unsigned char>(size >> (8 * i));
    return gzip;
  }
  std::string bytes_of(const std::string& name) {
    std::ifstream in(dir_.path() / name, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  std::vector<unsigned char> volume_ = std::vector<unsigned char>(13 * 11 * 9);
};

TEST_F(GzipTrailer, ThatUnderOrOverstatesCompleteDataDoesNotStopTheRun) {
  for (const std::uint32_t lie : {0u, 1000u, 5000u}) {
    SCOPED_TRACE(lie);
    write_nrrd("lying.nrrd", with_trailer_size(deflate_bytes(volume_, true), lie));
    const auto result = run_mvox("extract lying.nrrd -t 100 -o lying.ply -q", dir_.path());
    // zlib checks the trailer at the end of the stream: a wrong size is corrupt data, said so
    // before extraction (the measuring pass), or the mesh is the honest one.
    if (result.exit_code == 0) {
      EXPECT_TRUE(bytes_of("lying.ply") == bytes_of("honest.ply"));
    } else {
      test::expect_one_line_error(result, "lying.nrrd");
      EXPECT_NE(result.output.find("corrupt"), std::string::npos) << result.output;
    }
  }
}

TEST_F(GzipTrailer, ThatMatchesTheHeaderCannotPassShortData) {
  const std::vector<unsigned char> short_volume(volume_.begin(), volume_.end() - 200);
  // The trailer claims exactly the declared size: taken at its word, so the shortage is found
  // while streaming; the outputs are all or nothing anyway.
  write_nrrd("short.nrrd", with_trailer_size(deflate_bytes(short_volume, true),
                                             static_cast<std::uint32_t>(volume_.size())));
  expect_refused("extract short.nrrd -t 100", "short.nrrd", "compressed data");
  // The trailer tells the truth or claims less: measured, and refused before extraction.
  write_nrrd("short2.nrrd", deflate_bytes(short_volume, true));
  expect_refused("extract short2.nrrd -t 100", "short2.nrrd",
                 "compressed data hold 1087 bytes, expected 1287");
}

}  // namespace
}  // namespace mvox
