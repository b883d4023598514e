// NRRD and MetaImage volumes through the command line: bad volumes fail with one line and leave
// no output, a spacing or origin beyond float's range names the file, and a data file that is
// not a regular file (a FIFO, a device) is refused without opening it.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "command_runner.h"
#include "volume_files.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;
using test::volume_files::kDepth;
using test::volume_files::kHeight;
using test::volume_files::kSizes;
using test::volume_files::kWidth;
using test::volume_files::metaimage_fields;
using test::volume_files::write_file;

TEST(VolumeFilesCli, BadVolumesFailWithOneLineAndNoOutput) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  ScratchDirectory dir;
  const std::string header =
      std::string("NRRD0004\ntype: uchar\ndimension: 3\nsizes: ") + kSizes + "\nencoding: raw\n\n";
  write_file(dir / "cut.nrrd", header, std::vector<unsigned char>(raw.begin(), raw.end() - 100));
  write_file(dir / "int.nrrd",
             "NRRD0004\ntype: int\ndimension: 3\nsizes: 1 1 1\nendian: "
             "little\nencoding: raw\n\nxxxx");
  write_file(dir / "nodata.mhd", metaimage_fields("MET_UCHAR", "ElementDataFile = none.raw\n"));
  write_file(dir / "good.nrrd", header, raw);
  const std::string inputs = dir.listing();

  for (const char* input : {"cut.nrrd", "int.nrrd", "nodata.mhd"}) {
    expect_one_line_error(
        run_mvox(std::string("extract ") + input + " -t 100 -o out.ply --image out.png",
                 dir.path()),
        input);
    EXPECT_EQ(dir.listing(), inputs) << "an output or temporary was left behind";
  }
  // --raw with a file that has its own header is a usage error.
  expect_one_line_error(
      run_mvox("extract good.nrrd --raw 13x11x9:u8 -t 100 -o out.ply", dir.path()),
      "--raw: good.nrrd is a NRRD file with its own header", 2);
  EXPECT_EQ(dir.listing(), inputs);

  const test::CommandResult ok = run_mvox("extract good.nrrd -t 100 -o out.ply -q", dir.path());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(dir / "out.ply"));
}

// A spacing or origin that float coordinates cannot hold names the file and says "too large";
// a huge spacing used to overflow the length of its axis vector and be dropped for 1, silently.
TEST(VolumeFilesCli, SpacingOrOriginBeyondFloatNamesTheFile) {
  const std::vector<unsigned char> raw(2 * 2 * 2, 200);
  const std::string nrrd = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
  ScratchDirectory dir;
  write_file(dir / "spacings.nrrd", nrrd + "spacings: 1e300 1 1\n\n", raw);
  write_file(dir / "directions.nrrd",
             nrrd + "space: LPS\nspace directions: (1,0,0) (0,1e300,0) (0,0,1)\n\n", raw);
  write_file(dir / "origin.nrrd",
             nrrd +
                 "space: LPS\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: "
                 "(0,0,-1e39)\n\n",
             raw);
  write_file(dir / "reach.nrrd", nrrd + "spacings: 1 1 3e38\n\n", raw);
  write_file(dir / "spacing.mha",
             "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementSpacing = 1 1 1e300\n"
             "ElementDataFile = LOCAL\n",
             raw);
  const std::string inputs = dir.listing();
  const std::pair<const char*, const char*> cases[] = {
      {"spacings.nrrd",
       "spacing x is too large for float coordinates, got 1e+300 (usable: "
       "2.35099e-38 to 3.40282e+38)"},
      {"directions.nrrd", "spacing y is too large for float coordinates, got 1e+300"},
      {"origin.nrrd",
       "origin z is too large for float coordinates, got -1e+39 (usable: "
       "-3.40282e+38 to 3.40282e+38)"},
      {"reach.nrrd",
       "the mesh would reach 4.5e+38 along z, beyond float's range (at most "
       "3.40282e+38)"},
      {"spacing.mha", "spacing z is too large for float coordinates, got 1e+300"},
  };
  for (const auto& [input, problem] : cases) {
    // A picture alone is refused too: the report gives the placement, and it is the mesh's.
    for (const char* outputs : {" -o out.ply", " --image out.png"}) {
      expect_one_line_error(
          run_mvox(std::string("extract ") + input + " -t 100" + outputs, dir.path()),
          std::string("mvox: error: ") + input + ": " + problem);
      EXPECT_EQ(dir.listing(), inputs) << "an output or temporary was left behind";
    }
  }
  // Given --spacing, the reach is the option's doing: a usage error naming it.
  expect_one_line_error(
      run_mvox("extract spacings.nrrd -t 100 -o out.ply --spacing 1,1,3e38", dir.path()),
      "mvox: error: --spacing: the mesh would reach 4.5e+38 along z", 2);
  const test::CommandResult ok =
      run_mvox("extract spacings.nrrd -t 100 -o out.ply --spacing 1,1,1 -q", dir.path());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

// A detached data file that is a FIFO would keep mvox waiting in open() for a writer that never
// comes: refused before opening, naming header and data file. (timeout: a guard, so that a
// regression fails instead of hanging the suite.)
TEST(VolumeFilesCli, ADataFileThatIsNotARegularFileIsRefusedWithoutOpeningIt) {
  ScratchDirectory dir;
  ASSERT_EQ(::mkfifo((dir / "samples.raw").c_str(), 0600), 0);
  write_file(dir / "volume.nhdr",
             "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: "
             "samples.raw\n");
  write_file(
      dir / "volume.mhd",
      "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = samples.raw\n");
  write_file(dir / "device.mhd",
             "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = /dev/zero\n");
  for (const char* header : {"volume.nhdr", "volume.mhd"}) {
    expect_one_line_error(
        run_mvox(std::string("extract ") + header + " -t 100 -o out.ply", dir.path(), "timeout 30"),
        std::string("mvox: error: ") + header +
            ": data file samples.raw is a FIFO, not a regular file");
  }
  expect_one_line_error(run_mvox("extract device.mhd -t 100 -o out.ply", dir.path(), "timeout 30"),
                        "mvox: error: device.mhd: data file /dev/zero is a device, not a regular "
                        "file");
  EXPECT_EQ(dir.listing(), "device.mhd samples.raw volume.mhd volume.nhdr ");
}

}  // namespace
}  // namespace mvox
