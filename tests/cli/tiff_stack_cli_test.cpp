// A TIFF stack through the command line: extracted to a mesh, and refused in one line, with no
// output or temporary left, when the file is cut short.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "gtest/gtest.h"
#include "tiff_stack_files.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::ScratchDirectory;
using test::tiff_stack_files::kDepth;
using test::tiff_stack_files::kHeight;
using test::tiff_stack_files::kLayouts;
using test::tiff_stack_files::kWidth;
using test::tiff_stack_files::write_stack;

TEST(TiffStackCli, ExtractsAStackAndRefusesATruncatedOne) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  ScratchDirectory dir;
  write_stack(dir / "stack.tif", samples, kWidth, kHeight, 0, kDepth, kLayouts[3]);
  const test::CommandResult ok =
      test::run_mvox("extract stack.tif -t 25 -o stack.ply -q --stats stack.json", dir.path());
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(dir / "stack.ply"));

  fs::copy_file(dir / "stack.tif", dir / "cut.tif");
  fs::resize_file(dir / "cut.tif", fs::file_size(dir / "stack.tif") / 3);
  const std::string before = dir.listing();
  test::expect_one_line_error(test::run_mvox("extract cut.tif -t 25 -o cut.ply", dir.path()),
                              "cut.tif");
  EXPECT_EQ(dir.listing(), before) << "an output or temporary was left behind";
}

}  // namespace
}  // namespace mvox
