// Bad input files through the command line (the contract: support/bad_input.h): slices missing,
// dangling, directories, truncated, corrupt, in colour or unlike the first; folders and patterns
// with no slices; control characters in names kept to one line; raw volumes and slices of the
// wrong size, from a file, a pipe or a directory.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bad_input.h"
#include "command_runner.h"
#include "file_io.h"
#include "mvox_process.h"
#include "refusal.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::read_bytes;
using test::write_bytes;

using test::BadInput;
using test::FifoWriter;
using test::MvoxProcess;
using test::run_mvox;

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
  // The same bit flipped with the chunk's CRC made right again: damage only the decoders can
  // find, in the zlib stream. mvox's own PNG decoder leaves the file to libpng, which refuses it.
  const std::uint32_t length = std::uint32_t{static_cast<unsigned char>(good[33])} << 24 |
                               std::uint32_t{static_cast<unsigned char>(good[34])} << 16 |
                               std::uint32_t{static_cast<unsigned char>(good[35])} << 8 |
                               static_cast<unsigned char>(good[36]);
  ASSERT_EQ(good.substr(33 + 4, 4), "IDAT");
  const uLong crc = crc32(crc32(0, nullptr, 0),
                          reinterpret_cast<const Bytef*>(flipped.data()) + 33 + 4, length + 4);
  for (int i = 0; i < 4; ++i) flipped[33 + 8 + length + i] = static_cast<char>(crc >> (24 - 8 * i));
  write_bytes(slice, flipped);
  expect_refused("extract stack -t 128" + kOutputs, "stack/sphere_0005.png", "cannot decode PNG: ");
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
           {"12x10x9:u8", "ended after 960 bytes, expected 1080 for a 12x10x9 u8 volume"},
           {"12x10x7:u8", "holds more than the 840 bytes expected for a 12x10x7 u8 volume"}}) {
    std::thread feeder([&] {
      FifoWriter fifo(dir_ / "volume.raw");
      fifo.write(std::string(960, '\x80'));
    });
    expect_refused("extract volume.raw --raw " + spec + " -t 1" + kOutputs, "volume.raw", problem);
    feeder.join();
  }
}

TEST_F(BadInput, AVolumeOnStandardInputIsNamedSo) {
  // A user who piped the volume in typed "-" (or /dev/stdin): the message names what they gave,
  // not the device mvox opened for it.
  write_bytes(dir_ / "volume.raw", std::string(960, '\x80'));
  for (const std::string input : {"-", "/dev/stdin"}) {
    test::expect_refused(
        dir_.path(), "extract " + input + " --raw 12x10x9:u8 -t 1" + kOutputs, "standard input",
        "ended after 960 bytes, expected 1080 for a 12x10x9 u8 volume", 1, "cat volume.raw |");
    // Redirected from a file, standard input has a size, checked before anything is read.
    test::expect_refused(
        dir_.path(), "extract " + input + " --raw 12x10x9:u8 -t 1" + kOutputs + " < volume.raw",
        "standard input", "file is 960 bytes, expected 1080 for a 12x10x9 u8 volume", 1);
  }
}

// Formats are told apart by opening an input and reading its first bytes: a pipe gave those
// bytes to the first look, and a FIFO opened a second time waited for a writer that never came.
// Without --raw, a pipe, FIFO or device is refused before it is opened. (timeout: a guard, so
// that a regression fails instead of hanging the suite; no writer ever opens these FIFOs.)
TEST_F(BadInput, APipeOrDeviceWithoutRawIsRefusedBeforeItIsOpened) {
  const std::string kProblem =
      ", which mvox reads once, in order, as a raw volume: give --raw WxHxD:TYPE, or save it to "
      "a file to read another format";
  for (const std::string name : {"scan.png", "scan.nii", "scan.dcm", "scan.tif", "scan"}) {
    ASSERT_EQ(::mkfifo((dir_ / name).c_str(), 0600), 0);
    test::expect_refused(dir_.path(), "extract " + name + " -t 1" + kOutputs, name,
                         "is a FIFO" + kProblem, 2, "timeout 30");
    fs::remove(dir_ / name);
  }
  write_bytes(dir_ / "volume.raw", std::string(960, '\x80'));
  test::expect_refused(dir_.path(), "extract - -t 1" + kOutputs, "standard input",
                       "is a pipe" + kProblem, 2, "cat volume.raw | timeout 30");
  test::expect_refused(dir_.path(), "extract /dev/zero -t 1" + kOutputs, "/dev/zero",
                       "is a device" + kProblem, 2, "timeout 30");
}

TEST_F(BadInput, RawVolumeThatIsADirectory) {
  expect_refused("extract stack --raw 12x10x8:u8 -t 1" + kOutputs, "stack",
                 "is a directory; --raw 12x10x8 u8 reads one volume file");
}

}  // namespace
}  // namespace mvox
