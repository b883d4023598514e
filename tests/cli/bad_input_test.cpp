// Bad input never hurts: each way `mvox extract` can be given something wrong, run through the
// real command line. Every case checks the contract of README's "When things go wrong":
// - one line, "mvox: error: SUBJECT: PROBLEM", naming the file or option and the problem;
// - the exit code: 1 a failed job, 2 a usage error (plus a line pointing at --help),
//   128 + n for signal n (130 for SIGINT);
// - the directory exactly as it was: no new output, no temporary (".NAME.XXXXXX"), and the
//   previous outputs at the targets byte for byte. Most cases ask for all three outputs (mesh,
//   picture, report), created before extraction starts, so a failure mid-run must remove three
//   temporaries.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "jpeg_damage.h"
#include "mvox_process.h"
#include "refusal.h"
#include "tiff_bytes.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::read_bytes;
using test::write_bytes;

using test::CommandResult;
using test::MvoxProcess;
using test::run_mvox;
using test::ScratchDirectory;

// Every output a job can write, each with a previous version that must survive.
const char* const kPreviousOutputs[] = {"previous.ply", "previous.png", "previous.json"};
const std::string kOutputs = " -o previous.ply --image previous.png --stats previous.json -q";

// Writes into a FIFO that mvox reads, never waiting more than 30 s for mvox: a broken mvox
// must fail the test, not hang it.
class FifoWriter {
 public:
  explicit FifoWriter(const std::string& path) {
    // Writing to a FIFO whose reader has gone raises SIGPIPE, which would end the test binary.
    ::signal(SIGPIPE, SIG_IGN);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    // O_NONBLOCK: the open fails with ENXIO until mvox has the FIFO open for reading.
    while ((fd_ = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC)) < 0 && errno == ENXIO &&
           std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (fd_ < 0) ADD_FAILURE() << path << ": mvox did not open the FIFO within 30 s";
  }
  ~FifoWriter() { close(); }
  FifoWriter(const FifoWriter&) = delete;
  FifoWriter& operator=(const FifoWriter&) = delete;

  // True when every byte went in. Returns as soon as mvox has taken all but a pipe's capacity.
  bool write(const std::string& bytes) {
    std::size_t done = 0;
    while (fd_ >= 0 && done < bytes.size()) {
      pollfd ready{fd_, POLLOUT, 0};
      if (::poll(&ready, 1, 30000) <= 0) return false;
      const ssize_t put = ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (put < 0 && (errno == EAGAIN || errno == EINTR)) continue;
      if (put < 0) return false;
      done += static_cast<std::size_t>(put);
    }
    return done == bytes.size();
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    // An 8-bit stack of 8 slices of 12x10: a sphere with an inside at threshold 128.
    ASSERT_EQ(run_mvox("phantom sphere -o stack --size 12x10x8 -q", dir_.path()).exit_code, 0);
    for (const char* name : kPreviousOutputs)
      write_bytes(dir_ / name, std::string("the previous ") + name + ", which must survive\n");
  }

  // Runs `mvox ARGUMENTS` and checks the whole contract: one line starting
  // "mvox: error: SUBJECT" that says PROBLEM, the exit code, and nothing changed on disk: no
  // output or temporary left, the previous outputs and the inputs byte for byte as they were.
  void expect_refused(const std::string& arguments, const std::string& subject,
                      const std::string& problem, int exit_code = 1) {
    test::expect_refused(dir_.path(), arguments, subject, problem, exit_code);
  }

  // expect_refused for a job whose memory matters too: runs `mvox ARGUMENTS` without a shell
  // and returns its peak resident memory in KiB.
  long refused_peak_memory_kib(const std::vector<std::string>& arguments,
                               const std::string& subject, const std::string& problem) {
    const auto before = test::tree_snapshot(dir_.path());
    MvoxProcess mvox(arguments, dir_.path());
    const MvoxProcess::Ending ending = mvox.finish();
    test::expect_one_line_error({ending.exit_code, ending.errors}, subject);
    EXPECT_EQ(ending.errors.rfind("mvox: error: " + subject, 0), 0u) << ending.errors;
    EXPECT_NE(ending.errors.find(problem), std::string::npos)
        << "expected \"" << problem << "\" in: " << ending.errors;
    test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
    return ending.peak_memory_kib;
  }

  ScratchDirectory dir_;
};

// INPUT FILES ---------------------------------------------------------------------------------

TEST_F(BadInput, MissingSliceFile) {
  expect_refused(
      "extract stack/sphere_0000.png stack/sphere_0001.png stack/sphere_0009.png -t 128" + kOutputs,
      "stack/sphere_0009.png", "no such file or directory");
}

TEST_F(BadInput, SliceThatIsADanglingSymbolicLink) {
  // Unreadable even for root, unlike chmod 000. Skipping it would close the gap silently.
  fs::remove(dir_ / "stack/sphere_0004.png");
  fs::create_symlink("sphere_0004.png.lost", dir_ / "stack/sphere_0004.png");
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0004.png",
                 "is a dangling symbolic link");
  expect_refused("extract 'stack/*.png' -t 128" + kOutputs, "stack/sphere_0004.png",
                 "is a dangling symbolic link");
}

TEST_F(BadInput, SliceThatIsADirectory) {
  fs::remove(dir_ / "stack/sphere_0004.png");
  fs::create_directory(dir_ / "stack/sphere_0004.png");
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0004.png",
                 "is a directory, not a slice image");
}

TEST_F(BadInput, TruncatedImage) {
  // Slice 5 of 8: extraction is under way, the three temporaries exist when it fails.
  const std::string slice = dir_ / "stack/sphere_0005.png";
  fs::resize_file(slice, fs::file_size(slice) / 2);
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0005.png",
                 "truncated PNG: the file ends at byte");
}

TEST_F(BadInput, CorruptImages) {
  const std::string slice = dir_ / "stack/sphere_0005.png";
  const std::string good = read_bytes(slice);
  // Garbage with a .png name.
  std::string garbage(300, '\0');
  for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<char>(i * 37 + 11);
  write_bytes(slice, garbage);
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0005.png",
                 "cannot read image (unreadable, corrupt, truncated or not an image format)");
  // A PNG signature and garbage after it.
  write_bytes(slice, good.substr(0, 8) + garbage);
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0005.png",
                 "corrupt PNG: the first chunk is not a 13-byte IHDR");
  // One flipped bit in the pixel data, which starts after the signature and the IHDR chunk.
  std::string flipped = good;
  flipped[8 + 25 + 10] ^= 0x04;
  write_bytes(slice, flipped);
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0005.png", "fails its CRC check");
}

TEST_F(BadInput, ColourImage) {
  cv::Mat colour(10, 12, CV_8UC3, cv::Scalar(10, 200, 30));
  ASSERT_TRUE(cv::imwrite(dir_ / "stack/sphere_0005.png", colour));
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0005.png",
                 "colour image (3 channels)");
}

TEST_F(BadInput, SlicesOfDifferentSizes) {
  ASSERT_EQ(run_mvox("phantom sphere -o wide --size 14x10x2 -q", dir_.path()).exit_code, 0);
  fs::copy_file(dir_ / "wide/sphere_0000.png", dir_ / "stack/sphere_0008.png");
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0008.png",
                 "image is 14x10, expected 12x10 like the first slice");
}

TEST_F(BadInput, SlicesOfDifferentBitDepths) {
  ASSERT_EQ(run_mvox("phantom sphere -o deep --size 12x10x2 --bits 16 -q", dir_.path()).exit_code,
            0);
  fs::copy_file(dir_ / "deep/sphere_0001.png", dir_ / "stack/sphere_0008.png");
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0008.png",
                 "image is 16-bit unsigned, expected 8-bit unsigned like the first slice");
}

// JPEG AND TIFF DATA ---------------------------------------------------------------------------

// A stack of 8 JPEG slices written by OpenCV with a restart marker after every 8x8 block; slice
// 5 is replaced by `damage` of itself.
void write_jpeg_stack(
    const fs::path& dir,
    const std::function<std::vector<unsigned char>(std::vector<unsigned char>)>& damage) {
  fs::create_directories(dir);
  for (int z = 0; z < 8; ++z) {
    cv::Mat slice(48, 64, CV_8UC1);
    cv::randu(slice, 0, 255);
    slice(cv::Rect(32 - 2 * z, 24 - 2 * z, 1 + 4 * z, 1 + 4 * z)).setTo(250);
    std::vector<unsigned char> bytes;
    ASSERT_TRUE(cv::imencode(".jpg", slice, bytes, {cv::IMWRITE_JPEG_RST_INTERVAL, 1}));
    if (z == 5) bytes = damage(bytes);
    write_bytes((dir / ("slice_" + std::to_string(z) + ".jpg")).string(),
                std::string(bytes.begin(), bytes.end()));
  }
}

TEST_F(BadInput, JpegWithItsScanCutShortAndClosed) {
  // libjpeg fills the missing part with grey and only warns: OpenCV returned such slices.
  write_jpeg_stack(dir_ / "jpegs", [](std::vector<unsigned char> jpeg) {
    const test::ScanData scan = test::first_scan_data(jpeg);
    return test::cut_in_scan(jpeg, (scan.end - scan.begin) / 2);
  });
  expect_refused("extract jpegs -t 128" + kOutputs, "jpegs/slice_5.jpg",
                 "cannot decode JPEG: Corrupt JPEG data: ");
}

TEST_F(BadInput, JpegWithJunkRestartMarkers) {
  write_jpeg_stack(dir_ / "jpegs", test::renumber_restart_marker);
  expect_refused("extract jpegs -t 128" + kOutputs, "jpegs/slice_5.jpg",
                 "cannot decode JPEG: Corrupt JPEG data: found marker 0x");
  write_jpeg_stack(dir_ / "more_jpegs", [](const std::vector<unsigned char>& jpeg) {
    return test::insert_restart_markers(jpeg, 20);
  });
  expect_refused("extract more_jpegs -t 128" + kOutputs, "more_jpegs/slice_5.jpg",
                 "cannot decode JPEG: Corrupt JPEG data: ");
}

// A deflate page of 12x10 samples in one strip.
test::TiffPageBytes deflate_page(unsigned char value) {
  return {12, 10, 8, 8, 0, 0, 0, {test::zlib_compressed(std::vector<unsigned char>(120, value))}};
}

TEST_F(BadInput, TiffDeflateStripFailingItsChecksum) {
  std::vector<test::TiffPageBytes> pages;
  for (int z = 0; z < 8; ++z) pages.push_back(deflate_page(z > 1 && z < 6 ? 200 : 0));
  pages[5].chunks[0].back() ^= 0x01;  // the last byte of the Adler-32 checksum
  const std::vector<unsigned char> tiff = test::tiff_file_bytes(pages);
  write_bytes(dir_ / "stack.tif", std::string(tiff.begin(), tiff.end()));
  expect_refused("extract stack.tif -t 128" + kOutputs, "stack.tif",
                 "page 6: strip 0: corrupt deflate data (zlib: incorrect data check)");
}

// Lying headers must cost what their files hold, not what they declare. The whole process,
// shared libraries included, takes about 60 MB.
constexpr long kFarUnder200MiB = 200 * 1024;

TEST_F(BadInput, TiffWithTilesFarLargerThanItsImage) {
  // ~150 bytes declaring one 65536x65536 tile for a 12x10 image: 4.2 GB and 19 s before.
  const std::vector<unsigned char> tiff = test::tiff_file_bytes(
      {{12, 10, 8, 8, 0, 65536, 65536, {test::zlib_compressed(std::vector<unsigned char>(200))}}});
  write_bytes(dir_ / "tiles.tif", std::string(tiff.begin(), tiff.end()));
  const long peak = refused_peak_memory_kib(
      {"extract", "tiles.tif", "-t", "10", "-o", "previous.ply", "--image", "previous.png",
       "--stats", "previous.json", "-q"},
      "tiles.tif", "page 1: its 65536x65536 tiles are far larger than the 12x10 image");
  EXPECT_GT(peak, 0);
  EXPECT_LT(peak, kFarUnder200MiB) << "KiB at peak";
}

TEST_F(BadInput, TinyDeflateTiffDeclaringAHugePage) {
  // 30000x30000 samples declared by a 17-byte strip: std::bad_alloc after 1-1.9 GB before.
  const std::vector<unsigned char> tiff = test::tiff_file_bytes(
      {{30000, 30000, 8, 8, 0, 0, 0, {test::zlib_compressed(std::vector<unsigned char>(1000))}}});
  write_bytes(dir_ / "page.tif", std::string(tiff.begin(), tiff.end()));
  const long peak = refused_peak_memory_kib(
      {"extract", "page.tif", "-t", "10", "-o", "previous.ply", "--image", "previous.png",
       "--stats", "previous.json", "-q"},
      "page.tif",
      "page 1: strip 0 declares 900000000 bytes (30000 rows of 30000 8-bit unsigned samples) "
      "but stores 17 bytes of deflate data, which decode to at most 1032 times as many");
  EXPECT_GT(peak, 0);
  EXPECT_LT(peak, kFarUnder200MiB) << "KiB at peak";
}

TEST_F(BadInput, EmptyDirectoryNoImagesAndNoMatch) {
  fs::create_directory(dir_ / "empty");
  expect_refused("extract empty -t 128" + kOutputs, "empty", "directory is empty");
  fs::create_directory(dir_ / "notes");
  write_bytes(dir_ / "notes/readme.txt", "no slices here\n");
  expect_refused("extract notes -t 128" + kOutputs, "notes", "directory has no slice images");
  expect_refused("extract 'stack/*.tif' -t 128" + kOutputs, "stack/*.tif",
                 "no file matches this pattern");
  expect_refused("extract missing_dir -t 128" + kOutputs, "missing_dir",
                 "no such file or directory");
}

// A name may hold any byte but '/' and NUL. Printed as it is, a newline would split the error
// line in two and an escape sequence would reach the terminal: both are shown escaped.
TEST_F(BadInput, ControlCharactersInNamesStayInOneLine) {
  auto run = [&](const std::vector<std::string>& arguments) {
    MvoxProcess mvox(arguments, dir_.path());
    return mvox.finish();
  };
  MvoxProcess::Ending ending = run({"extract", "no\nsuch\x1b(B\t", "-t", "128", "-q"});
  EXPECT_EQ(ending.exit_code, 1);
  EXPECT_EQ(ending.errors, "mvox: error: no\\nsuch\\x1b(B\\x09: no such file or directory\n");
  // A usage error quotes the value; its second line is the pointer to --help.
  ending = run({"extract", "stack", "-t", "128", "-q", "--method", "a\nb\rc\x7f"});
  EXPECT_EQ(ending.exit_code, 2);
  EXPECT_EQ(ending.errors.substr(0, ending.errors.find('\n')),
            "mvox: error: --method: a\\nb\\x0dc\\x7f not in {voxels,cubes}");
  EXPECT_EQ(std::count(ending.errors.begin(), ending.errors.end(), '\n'), 2) << ending.errors;
  // The summary names the mesh, written under its real name.
  ending = run({"extract", "stack", "-t", "128", "-o", "mesh\n.ply"});
  EXPECT_EQ(ending.exit_code, 0) << ending.errors;
  EXPECT_EQ(ending.errors.rfind("mesh\\n.ply: ", 0), 0u) << ending.errors;
  EXPECT_TRUE(fs::exists(dir_ / "mesh\n.ply"));
  // A warning quotes what the environment says.
  const char* display = std::getenv("DISPLAY");
  const std::string saved = display != nullptr ? display : "";
  ::setenv("DISPLAY", ":59123\n", 1);  // no server listens on display 59123
  ending = run({"extract", "stack", "-t", "128", "--image", "picture.png", "--show", "-q"});
  if (display != nullptr)
    ::setenv("DISPLAY", saved.c_str(), 1);
  else
    ::unsetenv("DISPLAY");
  EXPECT_EQ(ending.exit_code, 0) << ending.errors;
  EXPECT_EQ(ending.errors.rfind("mvox: warning: --show: ", 0), 0u) << ending.errors;
  EXPECT_EQ(std::count(ending.errors.begin(), ending.errors.end(), '\n'), 1) << ending.errors;
}

// RAW INPUT -----------------------------------------------------------------------------------

TEST_F(BadInput, RawVolumeOfTheWrongSize) {
  write_bytes(dir_ / "volume.raw", std::string(12 * 10 * 8, '\x80'));
  expect_refused("extract volume.raw --raw 12x10x9:u8 -t 1" + kOutputs, "volume.raw",
                 "file is 960 bytes, expected 1080 for a 12x10x9 u8 volume");
  expect_refused("extract volume.raw --raw 12x10x7:u8 -t 1" + kOutputs, "volume.raw",
                 "file is 960 bytes, expected 840 for a 12x10x7 u8 volume");
}

TEST_F(BadInput, RawSliceOfTheWrongSize) {
  fs::create_directory(dir_ / "raw");
  for (int k = 0; k < 4; ++k)
    write_bytes(dir_ / ("raw/slice." + std::to_string(k)), std::string(k == 2 ? 119 : 120, '\0'));
  expect_refused("extract raw --raw 12x10:u8 -t 1" + kOutputs, "raw/slice.2",
                 "file is 119 bytes, expected 120 for one 12x10 u8 slice");
}

TEST_F(BadInput, RawVolumeFromAPipeOfTheWrongLength) {
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  // A pipe's length is only known as it arrives: short fails at the slice where it ends, long
  // after the last slice.
  for (const auto& [spec, problem] : std::vector<std::pair<std::string, std::string>>{
           {"12x10x9:u8", "file ended at byte 960, expected 1080 bytes"},
           {"12x10x7:u8", "holds more than the 840 bytes expected for a 12x10x7 u8 volume"}}) {
    std::thread feeder([&] {
      FifoWriter fifo(dir_ / "volume.raw");
      fifo.write(std::string(960, '\x80'));
    });
    expect_refused("extract volume.raw --raw " + spec + " -t 1" + kOutputs, "volume.raw", problem);
    feeder.join();
  }
}

TEST_F(BadInput, RawVolumeThatIsADirectory) {
  expect_refused("extract stack --raw 12x10x8:u8 -t 1" + kOutputs, "stack",
                 "is a directory; --raw 12x10x8 u8 reads one volume file");
}

// OPTIONS -------------------------------------------------------------------------------------

TEST_F(BadInput, UnknownOptionValuesAreUsageErrors) {
  const std::string job = "extract stack -t 128" + kOutputs;
  expect_refused(job + " --method foo", "--method", "foo not in {voxels,cubes}", 2);
  expect_refused(job + " --surface foo", "--surface", "foo not in {merge-rules,paper-table1}", 2);
  expect_refused(job + " --engine quick", "--engine", "quick not in {fast,literal}", 2);
  expect_refused(job + " --raw 12x10:u7", "--raw", "unknown sample type \"u7\"", 2);
  expect_refused(job + " --raw 3x3:u24", "--raw", "unknown sample type \"u24\"", 2);
  expect_refused(job + " --raw 12x10", "--raw", "expected WxH:TYPE", 2);
  expect_refused(job + " --raw 0x10:u8", "--raw", "width must be at least 1", 2);
  expect_refused(job + " --image-size 0x0", "--image-size", "'0x0' is not a picture size", 2);
  expect_refused(job + " --image-size 3x", "--image-size", "'3x' is not a picture size", 2);
  expect_refused(job + " --view 1,2,3,4", "--view", "At Most 3", 2);
  expect_refused(job + " --origin 1,nan,0", "--origin", "must be finite, got nan", 2);
}

// Numbers that are not what they seem: NaN passes CLI::Range (every comparison with it is
// false), sscanf's %u reads "1e3" as 1 and wraps "4294967808" around to 512, and strtoull reads
// "-1" as 2^64 - 1. Each is a usage error naming the option, in a line of reasonable length.
TEST_F(BadInput, NumbersOutsideTheirRangeAreUsageErrors) {
  const std::string job = "extract stack -t 128" + kOutputs;
  for (const char* view : {"nan,0", "0,nan", "0,0,nan", "inf,0", "0,-inf"})
    expect_refused(job + " --view " + view, "--view", "must be a number from -360 to 360, got ", 2);
  expect_refused(job + " --fov nan", "--fov", "must be a number from 1 to 170, got nan", 2);
  expect_refused(job + " --perspective --fov inf", "--fov", "from 1 to 170, got inf", 2);
  expect_refused(job + " --image-size 1e3", "--image-size", "'1e3' is not a picture size", 2);
  expect_refused(job + " --image-size 4294967808", "--image-size",
                 "'4294967808' is not a picture size", 2);
  expect_refused(job + " --image-size 64x4294967360", "--image-size",
                 "'64x4294967360' is not a picture size", 2);
  for (const char* size : {"+64", "-64", "' 64'", "64x+64", "0x40", "64.0"})
    expect_refused(job + " --image-size " + size, "--image-size", "is not a picture size", 2);
  expect_refused(job + " --every 1e3", "--every",
                 "must be a whole number from 1 to 1073741824, got 1e3", 2);
  expect_refused(job + " --every 4294967297", "--every", "got 4294967297", 2);
  // CLI::PositiveNumber's refusal printed its bound, DBL_MAX, with some 310 digits.
  for (const char* spacing : {"0,1,1", "1,-2,1", "1,1,nan", "inf,1,1"}) {
    expect_refused(job + " --spacing " + spacing, "--spacing", "must be positive and finite, got ",
                   2);
  }
  expect_refused(job + " --spacing 1,1,1e300", "--spacing",
                 "is too large for float coordinates, got 1e300 (usable: 2.35099e-38 to "
                 "3.40282e+38)",
                 2);
  expect_refused(job + " --origin 0,-1e39,0", "--origin",
                 "is too large for float coordinates, got -1e39", 2);
  // The other subcommands' numbers.
  expect_refused("demo --size 1e2" + kOutputs, "--size",
                 "must be a whole number from 2 to 4096, got 1e2", 2);
  expect_refused("demo --view 0,nan" + kOutputs, "--view", "got nan", 2);
  expect_refused("render previous.ply -o previous.png --fov nan -q", "--fov", "got nan", 2);
  expect_refused("render previous.ply -o previous.png --view nan,0 -q", "--view", "got nan", 2);
  expect_refused("phantom sphere -o more --seed -1 -q", "--seed",
                 "must be a whole number from 0 to 18446744073709551615, got -1", 2);
  expect_refused("phantom sphere -o more --seed 18446744073709551616 -q", "--seed",
                 "got 18446744073709551616", 2);
}

TEST_F(BadInput, WholeNumbersAreReadInDecimal) {
  // strtoull, CLI11's reader, takes "010" as octal 8 and "0x10" as 16; mvox means 10, and
  // refuses 0x10. Frames every 010 slices of 24: frame_0010, frame_0020 and the last, frame_0024.
  ASSERT_EQ(run_mvox("phantom sphere -o tall --size 12x10x24 -q", dir_.path()).exit_code, 0);
  const CommandResult result =
      run_mvox("extract tall -t 128 --image p.png --frames frames --every 010 -q", dir_.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::vector<std::string> frames;
  for (const auto& entry : fs::directory_iterator(dir_ / "frames"))
    frames.push_back(entry.path().filename().string());
  std::sort(frames.begin(), frames.end());
  EXPECT_EQ(frames,
            (std::vector<std::string>{"frame_0010.png", "frame_0020.png", "frame_0024.png"}));
  expect_refused("demo --size 0x10" + kOutputs, "--size", "got 0x10", 2);
}

TEST_F(BadInput, ThresholdOutsideTheSampleRange) {
  expect_refused("extract stack -t 300" + kOutputs, "stack",
                 "threshold 300 is above the largest u8 sample (255): no voxel would be inner");
  expect_refused("extract stack -t 0" + kOutputs, "stack",
                 "threshold 0 is not above the smallest u8 sample (0): every voxel would be inner");
  write_bytes(dir_ / "volume.raw", std::string(12 * 10 * 4 * 2, '\0'));
  expect_refused("extract volume.raw --raw 12x10x4:u16le -t 70000" + kOutputs, "volume.raw",
                 "above the largest u16 sample (65535)");
  expect_refused("extract volume.raw --raw 12x10x4:i16le -t -40000" + kOutputs, "volume.raw",
                 "not above the smallest i16 sample (-32768)");
  expect_refused("extract stack -t nan" + kOutputs, "--threshold", "'nan' is not a finite number",
                 2);
  expect_refused("extract stack" + kOutputs, "--threshold", "is required", 2);
}

// OUTPUTS -------------------------------------------------------------------------------------

TEST_F(BadInput, OutputDirectoryThatDoesNotExist) {
  expect_refused("extract stack -t 128 -o no/such/dir/mesh.ply", "no/such/dir/mesh.ply",
                 "cannot create file: No such file or directory");
  expect_refused("extract stack -t 128 -o previous.ply --image no/dir/picture.png",
                 "no/dir/picture.png", "cannot create file: No such file or directory");
  expect_refused("extract stack -t 128 -o previous.ply --stats no/dir/stats.json",
                 "no/dir/stats.json", "cannot create file: No such file or directory");
}

TEST_F(BadInput, OutputDirectoryNotWritable) {
  // Root may write anywhere it has permission bits for, but not under a regular file, nor in
  // /proc.
  write_bytes(dir_ / "file.txt", "a file, not a directory\n");
  expect_refused("extract stack -t 128 -o file.txt/mesh.ply", "file.txt/mesh.ply",
                 "cannot create file: Not a directory");
  expect_refused("extract stack -t 128 -o previous.ply --image file.txt/picture.png",
                 "file.txt/picture.png", "cannot create file: Not a directory");
  fs::create_directory(dir_ / "folder");
  expect_refused("extract stack -t 128 -o folder", "folder", "cannot create file: Is a directory");
  if (!fs::is_directory("/proc/self")) GTEST_SKIP() << "no /proc: its case is not tried";
  expect_refused("extract stack -t 128 -o /proc/mesh.ply", "/proc/mesh.ply", "cannot create file");
}

TEST_F(BadInput, FullDisk) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full: the full-disk cases are not tried";
  expect_refused("extract stack -t 128 -o /dev/full --image previous.png -q", "/dev/full",
                 "write failed: No space left on device");
  // The picture goes through OutputFile too; its name needs an image extension.
  fs::create_symlink("/dev/full", dir_ / "full.png");
  expect_refused("extract stack -t 128 -o previous.ply --image full.png -q", "full.png",
                 "write failed: No space left on device");
  expect_refused("extract stack -t 128 -o previous.ply --stats /dev/full -q", "/dev/full",
                 "write failed: No space left on device");
}

TEST_F(BadInput, FileSizeLimit) {
  // ulimit -f would kill mvox with SIGXFSZ, its temporaries left behind, if mvox did not
  // ignore that signal; the write fails instead, like on a full disk. A mesh larger than the
  // limit of 4 blocks (2 KiB in dash, 4 KiB in bash):
  ASSERT_EQ(run_mvox("phantom sphere -o big --size 40x40x30 -q", dir_.path()).exit_code, 0);
  const auto before = test::tree_snapshot(dir_.path());
  const CommandResult result =
      run_mvox("extract big -t 128 -o previous.ply -q", dir_.path(), "ulimit -f 4;");
  test::expect_one_line_error(result, "previous.ply");
  // The mesh's faces wait in a scratch file beside it, which may hit the limit first.
  EXPECT_EQ(result.output.rfind("mvox: error: previous.ply: write failed", 0), 0u) << result.output;
  EXPECT_NE(result.output.find(": File too large"), std::string::npos) << result.output;
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

TEST_F(BadInput, OutputsThatCollide) {
  expect_refused("extract stack -t 128 -o previous.ply --stats previous.ply", "previous.ply",
                 "is both the mesh (-o previous.ply) and the report (--stats previous.ply)", 2);
  expect_refused("extract stack -t 128 -o previous.png --format ply --image previous.png",
                 "previous.png", "is both the mesh (-o previous.png) and the picture", 2);
  expect_refused("extract stack -t 128 -q", "stack", "nothing to write");
  // A phantom into a folder that holds slices would silently mix two stacks.
  expect_refused("phantom torus -o stack --size 12x10x3 -q", "stack", "already exists");
}

// INTERRUPTS AND PIPES ------------------------------------------------------------------------

// 256x256 slices of 8 bits are 64 KiB, a pipe's capacity: once the test has written slice k
// into the FIFO, mvox has read slice k - 2 at least. The reading thread then sits in read(),
// waiting for slices that do not come, when the signal arrives.
constexpr int kSide = 256;
constexpr int kDepth = 16;

std::string raw_slice(int z) {
  std::string slice(kSide * kSide, '\0');
  for (int y = 64; y < 192; ++y)
    for (int x = 64; x < 192; ++x) slice[y * kSide + x] = z > 0 ? '\xc8' : '\0';
  return slice;
}

std::vector<std::string> interrupted_job() {
  return {
      "extract",
      "volume.raw",
      "--raw",
      std::to_string(kSide) + "x" + std::to_string(kSide) + "x" + std::to_string(kDepth) + ":u8",
      "-t",
      "128",
      "-o",
      "previous.ply",
      "--image",
      "previous.png",
      "--stats",
      "previous.json",
      "-q"};
}

const char* signal_name(int signal_number) {
  switch (signal_number) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
  }
  return "?";
}

class Interrupt : public BadInput, public ::testing::WithParamInterface<int> {};

TEST_P(Interrupt, MidRunLeavesNothingAndExitsWith128PlusTheSignal) {
  const int signal_number = GetParam();
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  const auto before = test::tree_snapshot(dir_.path());

  MvoxProcess mvox(interrupted_job(), dir_.path());
  FifoWriter fifo(dir_ / "volume.raw");
  for (int z = 0; z < 3; ++z) ASSERT_TRUE(fifo.write(raw_slice(z))) << "slice " << z;
  // Mid-run for sure: the outputs' three temporaries are there.
  std::size_t temporaries = 0;
  for (const auto& entry : fs::directory_iterator(dir_.path()))
    temporaries += entry.path().filename().string().rfind(".previous.", 0) == 0;
  EXPECT_EQ(temporaries, 3u) << dir_.listing();

  mvox.send(signal_number);
  const MvoxProcess::Ending ending = mvox.finish();
  fifo.close();
  EXPECT_EQ(ending.signal, 0);
  EXPECT_EQ(ending.exit_code, 128 + signal_number);
  EXPECT_EQ(ending.errors, std::string("mvox: error: previous.ply: interrupted by ") +
                               signal_name(signal_number) + "\n");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

INSTANTIATE_TEST_SUITE_P(BadInput, Interrupt, ::testing::Values(SIGINT, SIGTERM, SIGHUP),
                         [](const ::testing::TestParamInfo<int>& info) {
                           return std::string(signal_name(info.param));
                         });

// A job that fails mid-volume while the FIFO it reads from stays open and silent: the reading
// thread is blocked in read(), and mvox must still end at once with its error (read
// cancellation, src/read/read_cancellation.h), not wait for a writer that may never close.
TEST_F(BadInput, AnErrorWhileTheInputPipeStaysOpenEndsTheRunAtOnce) {
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  std::vector<std::string> job = interrupted_job();
  // The frame after slice 5 cannot be written, its name being taken by a directory: an error
  // mid-volume. (A placement past float's range, used before, is now refused before the run.)
  ASSERT_TRUE(fs::create_directories(dir_ / "frames/frame_0005.png"));
  for (const char* extra : {"--frames", "frames", "--every", "5"}) job.push_back(extra);
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox(job, dir_.path());
  FifoWriter fifo(dir_ / "volume.raw");
  // Seven slices are just enough for the error (found by trying; the picture's normals keep the
  // engine a slice behind): the reader, reading ahead, is then blocked in read() for the eighth.
  for (int z = 0; z < 7; ++z) ASSERT_TRUE(fifo.write(raw_slice(z))) << "slice " << z;
  // The FIFO stays open (no end of file) until after mvox has finished; finish() fails the test
  // if that takes 60 s.
  const MvoxProcess::Ending ending = mvox.finish();
  fifo.close();
  EXPECT_EQ(ending.exit_code, 1);
  EXPECT_NE(ending.errors.find("mvox: error: frames/frame_0005.png: "), std::string::npos)
      << ending.errors;
  EXPECT_EQ(std::count(ending.errors.begin(), ending.errors.end(), '\n'), 1) << ending.errors;
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

// True once a thread of process `pid` waits in open() for a FIFO's writer.
bool waits_for_fifo_writer(pid_t pid) {
  std::error_code error;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", error))
    if (read_bytes((task.path() / "wchan").string()) == "wait_for_partner") return true;
  return false;
}

TEST_F(BadInput, InterruptWhileWaitingForTheInputNamesIt) {
  ASSERT_EQ(::mkfifo((dir_ / "volume.raw").c_str(), 0600), 0);
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox(interrupted_job(), dir_.path());
  // No writer: mvox blocks in open(), before any output exists.
  bool waiting = false;
  for (int i = 0; i < 1000 && !waiting; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    waiting = waits_for_fifo_writer(mvox.pid());
  }
  if (!waiting) GTEST_SKIP() << "cannot see mvox wait in open() (/proc/PID/task/*/wchan)";
  mvox.send(SIGINT);
  const MvoxProcess::Ending ending = mvox.finish();
  EXPECT_EQ(ending.exit_code, 130);
  EXPECT_EQ(ending.errors, "mvox: error: volume.raw: interrupted by SIGINT\n");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

TEST_F(BadInput, ReaderClosingTheOutputPipeEndsMvoxQuietly) {
  // `mvox extract ... -o - | head -c 10`: a mesh far larger than the pipe's 64 KiB, so mvox is
  // still writing when the reader goes.
  ASSERT_EQ(run_mvox("phantom sphere -o big --size 96x96x64 -q", dir_.path()).exit_code, 0);
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox({"extract", "big", "-t", "128", "-o", "-", "--image", "previous.png", "--stats",
                    "previous.json", "-q"},
                   dir_.path(), /*own_stdout=*/true);
  EXPECT_EQ(mvox.read_stdout(10), "ply\nformat");
  mvox.close_stdout();
  const MvoxProcess::Ending ending = mvox.finish();
  // As `cat` or `grep` end in a pipeline: killed by SIGPIPE (status 141 in the shell), no
  // message; the picture and the report, which could not appear together with the mesh, do not.
  EXPECT_EQ(ending.signal, SIGPIPE) << "exit code " << ending.exit_code << ": " << ending.errors;
  EXPECT_EQ(ending.errors, "");
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
}

}  // namespace
}  // namespace mvox
