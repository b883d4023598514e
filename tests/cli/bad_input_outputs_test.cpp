// Outputs that cannot be written, through the command line (the contract: support/bad_input.h):
// a missing or unwritable folder, a full disk, the file size limit, and outputs that collide.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "bad_input.h"
#include "command_runner.h"
#include "file_io.h"
#include "refusal.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::write_bytes;

using test::BadInput;
using test::CommandResult;
using test::run_mvox;

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

// What a command prints on standard output (--dry-run's plan, --help) went onto a full disk with
// exit 0: it is checked at the end. A reader that has gone ends mvox quietly, as for a mesh.
TEST_F(BadInput, StandardOutputThatCannotBeWrittenFailsTheCommand) {
  for (const std::string arguments : {"extract stack -t 128 -o mesh.ply --dry-run", "--help"}) {
    SCOPED_TRACE(arguments);
    const test::CommandResult full =
        test::run_mvox(arguments + " > /dev/full; }", dir_.path(), "{");
    EXPECT_EQ(full.exit_code, 1);
    EXPECT_EQ(full.output.rfind("mvox: error: standard output: write failed", 0), 0u)
        << full.output;
    EXPECT_EQ(std::count(full.output.begin(), full.output.end(), '\n'), 1) << full.output;
    // The reader exits before mvox writes (sleep): the write finds the pipe closed.
    const test::CommandResult closed = test::run_mvox(
        arguments + "; echo \"exit $?\" >&2) | true; }", dir_.path(), "{ (sleep 0.3;");
    EXPECT_EQ(closed.output, "exit 141\n");
  }
}

TEST_F(BadInput, OutputsThatCollide) {
  expect_refused("extract stack -t 128 -o previous.ply --stats previous.ply", "previous.ply",
                 "is both the mesh (-o previous.ply) and the report (--stats previous.ply)", 2);
  expect_refused("extract stack -t 128 -o previous.png --format ply --image previous.png",
                 "previous.png", "is both the mesh (-o previous.png) and the picture", 2);
  expect_refused("extract stack -t 128 -q", "stack", "nothing to write", 2);
  // A phantom into a folder that holds slices would silently mix two stacks.
  expect_refused("phantom torus -o stack --size 12x10x3 -q", "stack", "already exists");
  // A slice that cannot be written is named where the stack would have been, not in the hidden
  // folder it is written into, which is gone once the run has failed.
  test::expect_refused(dir_.path(), "phantom blobs -o made --size 256x256x4 -q",
                       "made/blobs_0000.png", "write failed: File too large", 1, "ulimit -f 1;");
}

}  // namespace
}  // namespace mvox
