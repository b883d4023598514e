// The input-format table (src/read/input_format.h): which row takes each kind of INPUT, and the
// refusals written once for all rows (options that do not fit the input are usage errors).
#include "read/input_format.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "command_runner.h"
#include "error.h"
#include "file_io.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::run_mvox;
using test::ScratchDirectory;
using test::write_bytes;

// The name of the first row that claims `inputs` with `options`.
std::string claimed_by(const std::vector<std::string>& inputs, const InputOptions& options = {}) {
  const InputRequest request(inputs, options);
  for (const InputFormat* format : input_formats())
    if (format->claims(request)) return format->name;
  return "(none)";
}

class InputFormatTable : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_mvox("phantom sphere -o stack --size 12x10x4 -q", dir_.path()).exit_code, 0);
    write_bytes(dir_.path() / "v.nrrd",
                "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" +
                    std::string(8, '\0'));
    write_bytes(dir_.path() / "v.mha",
                "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n"
                "ElementDataFile = LOCAL\n" +
                    std::string(8, '\0'));
    write_bytes(dir_.path() / "v.raw", std::string(8, '\0'));
    fs::create_directory(dir_.path() / "dicom");
    write_bytes(dir_.path() / "dicom/a.dcm", std::string(128, '\0') + "DICM");
    fs::create_directory(dir_.path() / "tiffs");
    write_bytes(dir_.path() / "tiffs/a.tif", "II*");
  }
  std::string path(const char* name) const { return (dir_.path() / name).string(); }
  ScratchDirectory dir_;
};

TEST_F(InputFormatTable, EachKindOfInputIsClaimedByItsRow) {
  InputOptions raw_volume, raw_slices, forced;
  raw_volume.raw = parse_raw_format("2x2x2:u8");
  raw_slices.raw = parse_raw_format("2x2:u8");
  forced.dicom.force = true;
  EXPECT_EQ(claimed_by({path("stack")}), "image stack");
  EXPECT_EQ(claimed_by({path("v.nrrd")}), "NRRD volume");
  EXPECT_EQ(claimed_by({path("v.mha")}), "MetaImage volume");
  EXPECT_EQ(claimed_by({path("tiffs")}), "TIFF stack");
  EXPECT_EQ(claimed_by({path("dicom")}), "DICOM series");
  EXPECT_EQ(claimed_by({path("v.raw")}, raw_volume), "raw volume");
  EXPECT_EQ(claimed_by({path("v.raw")}, raw_slices), "raw slices");
  EXPECT_EQ(claimed_by({path("stack")}, forced), "DICOM series");
  // TIFF files among other images stay an image stack.
  EXPECT_EQ(claimed_by({path("tiffs/a.tif"), path("stack/sphere_0000.png")}), "image stack");
}

TEST_F(InputFormatTable, OptionsThatDoNotFitTheInputAreUsageErrors) {
  InputOptions raw;
  raw.raw = parse_raw_format("2x2x2:u8");
  for (const char* headered : {"v.nrrd", "v.mha"}) {
    try {
      open_input({path(headered)}, raw);
      ADD_FAILURE() << headered << " opened with --raw";
    } catch (const UsageError& error) {
      EXPECT_EQ(error.subject(), "--raw");
      EXPECT_NE(error.problem().find("with its own header; leave --raw out"), std::string::npos);
    }
  }
  InputOptions series;
  series.dicom.series_uid = "1.2.3";
  EXPECT_THROW(open_input({path("stack")}, series), UsageError);
  InputOptions both = raw;
  both.dicom.force = true;
  EXPECT_THROW(open_input({path("v.raw")}, both), UsageError);
  // Through the command line: exit 2, before any file is opened.
  test::expect_one_line_error(run_mvox("extract v.nrrd --raw 2x2x2:u8 -t 1 -o m.ply", dir_.path()),
                              "--raw", 2);
}

TEST_F(InputFormatTable, AHeaderedVolumeMustBeTheOnlyInput) {
  try {
    open_input({path("v.nrrd"), path("v.mha")}, {});
    ADD_FAILURE() << "two volumes opened as one";
  } catch (const Error& error) {
    EXPECT_NE(error.problem().find("volume, which must be the only input (got 2 files)"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace mvox
