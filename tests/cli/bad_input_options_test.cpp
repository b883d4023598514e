// Bad options through the command line (the contract: support/bad_input.h): unknown values and
// numbers outside their range are usage errors naming the option, whole numbers are decimal,
// and a threshold outside the sample range is refused naming the input.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "bad_input.h"
#include "command_runner.h"
#include "file_io.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::write_bytes;

using test::BadInput;
using test::CommandResult;
using test::run_mvox;

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
  for (const char* cut : {"nan", "-0.1", "1.5", "inf"})
    expect_refused(job + " --cut " + cut, "--cut", "must be a number from 0 to 1, got ", 2);
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
  // A tuning option once hidden from --help, whose refusals then named no option (": Value 2").
  for (const char* slices : {"2", "abc", "1e3"})
    expect_refused(job + " --threads 2 --slab-slices " + slices, "--slab-slices",
                   std::string("must be a whole number from 4 to 1073741824, got ") + slices, 2);
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

}  // namespace
}  // namespace mvox
