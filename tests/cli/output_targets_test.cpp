// No output may replace an input, or another output (src/write/output_targets.h), whatever the
// names: each way a user can point an output at a file that matters, run through the real command
// line. A refusal is a usage error (exit 2) found before anything is read or written, and the
// whole directory, inputs included, stays byte for byte as it was. Outputs that only share a
// directory with the input, or that name a discarding device twice, are fine.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "command_runner.h"
#include "file_io.h"
#include "read/ply/ply_reader.h"
#include "refusal.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::read_bytes;
using test::write_bytes;

using test::run_mvox;
using test::ScratchDirectory;

class OutputTargets : public ::testing::Test {
 protected:
  void SetUp() override {
    // An 8-slice 12x10 sphere stack, the same volume as a raw file, and previous outputs.
    ASSERT_EQ(run_mvox("phantom sphere -o stack --size 12x10x8 -q", dir_.path()).exit_code, 0);
    std::string volume;
    for (int z = 0; z < 8; ++z)
      for (int i = 0; i < 120; ++i) volume += static_cast<char>((i + 7 * z) % 200);
    write_bytes(dir_.path() / "volume.raw", volume);
    write_bytes(dir_.path() / "previous.ply", "the previous mesh\n");
    write_bytes(dir_.path() / "previous.json", "the previous report\n");
  }

  void expect_refused(const std::string& arguments, const std::string& subject,
                      const std::string& problem) {
    test::expect_refused(dir_.path(), arguments, subject, problem, 2);
  }

  ScratchDirectory dir_;
};

const std::string kRaw = " --raw 12x10x8:u8 -t 100 -q";

TEST_F(OutputTargets, AnInputIsNeverReplacedByTheMeshPictureOrReport) {
  // The cases of the issue: the scan replaced by its own mesh, and a slice of the stack.
  expect_refused("extract volume.raw" + kRaw + " --format ply -o volume.raw", "volume.raw",
                 "is an input file, and the mesh (-o) would replace it");
  expect_refused("extract stack -t 128 -q --format ply -o stack/sphere_0000.png",
                 "stack/sphere_0000.png", "is an input file, and the mesh (-o) would replace it");
  expect_refused("extract stack -t 128 -q --image stack/sphere_0003.png", "stack/sphere_0003.png",
                 "the picture (--image) would replace it");
  expect_refused("extract volume.raw" + kRaw + " -o mesh.ply --stats volume.raw", "volume.raw",
                 "the report (--stats) would replace it");
  // A glob names the same files as the directory does.
  expect_refused("extract 'stack/*.png' -t 128 -q --format ply -o stack/sphere_0007.png",
                 "stack/sphere_0007.png", "is an input file");
}

TEST_F(OutputTargets, RenderComparesItsMeshByPathBeforeOpeningIt) {
  // The mesh is checked before it is read, so it may not exist: a new output and a missing mesh
  // are still one path when named alike (the run would otherwise fail on the mesh).
  fs::create_directory(dir_.path() / "sub");
  expect_refused("render missing.png -o missing.png", "missing.png", "is an input file");
  expect_refused("render missing.png -o sub/../missing.png", "sub/../missing.png",
                 "is the input missing.png by another name");
}

TEST_F(OutputTargets, OtherSpellingsAndLinksOfAnInputAreTheSameFile) {
  fs::create_symlink("volume.raw", dir_.path() / "soft.ply");
  fs::create_hard_link(dir_.path() / "volume.raw", dir_.path() / "hard.ply");
  fs::create_directory(dir_.path() / "sub");
  expect_refused("extract volume.raw" + kRaw + " --format ply -o ./sub/../volume.raw",
                 "./sub/../volume.raw", "is the input volume.raw by another name");
  expect_refused("extract volume.raw" + kRaw + " -o soft.ply", "soft.ply",
                 "is the input volume.raw by another name");
  expect_refused("extract volume.raw" + kRaw + " -o hard.ply", "hard.ply",
                 "is the input volume.raw by another name");
  // The shell's redirection makes /dev/stdin the input file, and so any name of descriptor 0.
  expect_refused("extract /dev/stdin" + kRaw + " -o m.ply --stats /proc/self/fd/0 < volume.raw",
                 "/proc/self/fd/0", "is the input /dev/stdin by another name");
}

TEST_F(OutputTargets, ADetachedDataFileIsAnInputToo) {
  write_bytes(dir_.path() / "volume.nhdr",
              "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 12 10 8\nencoding: raw\n"
              "data file: volume.raw\n");
  write_bytes(dir_.path() / "volume.mhd",
              "NDims = 3\nDimSize = 12 10 8\nElementType = MET_UCHAR\n"
              "ElementDataFile = volume.raw\n");
  expect_refused("extract volume.nhdr -t 100 -q --format ply -o volume.raw", "volume.raw",
                 "is an input file");
  expect_refused("extract volume.mhd -t 100 -q --stats volume.raw -o m.ply", "volume.raw",
                 "is an input file");
  expect_refused("extract volume.nhdr -t 100 -q --format ply -o volume.nhdr", "volume.nhdr",
                 "is an input file");
}

TEST_F(OutputTargets, OutputsBesideTheInputsUnderOtherNamesAreFine) {
  const auto result =
      run_mvox("extract stack -t 128 -q -o stack/mesh.ply --image stack/pic.png", dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir_.path() / "stack/mesh.ply"));
  EXPECT_TRUE(fs::exists(dir_.path() / "stack/pic.png"));
}

TEST_F(OutputTargets, TwoOutputsOnOneFileAreRefusedForEveryPair) {
  expect_refused("extract stack -t 128 -q -o x.ply --stats ./x.ply", "./x.ply",
                 "is both the mesh (-o x.ply) and the report (--stats ./x.ply)");
  expect_refused("extract stack -t 128 -q -o x.png --format ply --image x.png", "x.png",
                 "is both the mesh (-o x.png) and the picture (--image x.png)");
  expect_refused("extract stack -t 128 -q --image x.png --stats sub/../x.png", "sub/../x.png",
                 "is both the picture (--image x.png) and the report (--stats sub/../x.png)");
  // Existing outputs by identity: a link to another output.
  fs::create_symlink("previous.ply", dir_.path() / "alias.json");
  expect_refused("extract stack -t 128 -q -o previous.ply --stats alias.json", "alias.json",
                 "is both the mesh (-o previous.ply) and the report (--stats alias.json)");
  // The frames: the last of 8 slices is frame_0008.png, frame_0004.png comes after 4 of them.
  expect_refused("extract stack -t 128 -q --frames f --every 4 --image f/frame_0008.png",
                 "f/frame_0008.png", "is both the picture (--image f/frame_0008.png) and a frame");
  expect_refused("extract stack -t 128 -q --frames f --every 2 --format ply -o f/frame_0004.png",
                 "f/frame_0004.png", "and a frame of --frames f");
  expect_refused(
      "extract stack -t 128 -q --frames . --every 4 --image p.png --stats frame_0004.png",
      "frame_0004.png", "is both the report (--stats frame_0004.png) and a frame");
  // Standard output, however it is named.
  expect_refused("extract stack -t 128 -q -o - --stats -", "standard output",
                 "is both the mesh (-o -) and the report (--stats -)");
  expect_refused("extract stack -t 128 -q -o - --image /dev/stdout", "/dev/stdout",
                 "is both the mesh (-o -) and the picture (--image /dev/stdout)");
  expect_refused("extract stack -t 128 -q -o /proc/self/fd/1 --stats /dev/fd/1", "/dev/fd/1",
                 "is both the mesh");
}

TEST_F(OutputTargets, NamesAFrameWouldTakeAreRefusedOnlyWhenAFrameTakesThem) {
  fs::create_directory(dir_.path() / "scans");
  for (int z = 0; z < 8; ++z) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", z);
    fs::copy_file(dir_.path() / ("stack/sphere_000" + std::to_string(z) + ".png"),
                  dir_.path() / "scans" / name);
  }
  // Frames after 2, 4, 6 and 8 slices: frame_0002.png would replace an input slice.
  expect_refused("extract scans -t 128 -q --frames scans --every 2", "--frames scans",
                 "a frame would replace the input scans/frame_0002.png");
  // After every 9th slice and at the end (8): no input is named frame_0008.png.
  const auto result = run_mvox("extract scans -t 128 -q --frames scans --every 9", dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir_.path() / "scans/frame_0008.png"));
}

TEST_F(OutputTargets, DiscardingDevicesMayBeNamedTwice) {
  const auto result = run_mvox(
      "extract stack -t 128 -q -o /dev/null --stats /dev/null "
      "--image /dev/null",
      dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
}

// Standard output redirected to a file and named as /dev/stdout or /proc/self/fd/1 is written
// through: as root, a rename would replace the /dev/stdout link itself and leave the file empty.
TEST_F(OutputTargets, DescriptorPathsAreWrittenThroughNotRenamedOver) {
  ASSERT_EQ(run_mvox("extract stack -t 128 -q -o reference.ply", dir_.path()).exit_code, 0);
  auto result = run_mvox("extract stack -t 128 -q -o /dev/stdout > through.ply", dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  // The same mesh; the header differs only in padding (a pipe-like target gets no reserve).
  const PlyMesh through = read_ply((dir_.path() / "through.ply").string());
  const PlyMesh reference = read_ply((dir_.path() / "reference.ply").string());
  EXPECT_TRUE(through.positions == reference.positions);
  EXPECT_TRUE(through.face_indices == reference.face_indices);
  EXPECT_GT(reference.face_count(), 0u);
  result = run_mvox("extract stack -t 128 -q -o mesh.ply --stats /proc/self/fd/1 > report.json",
                    dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(read_bytes(dir_.path() / "report.json").rfind("{\n", 0), 0u);
  result = run_mvox("extract stack -t 128 -q --image /dev/fd/1 > picture.png", dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(read_bytes(dir_.path() / "picture.png").substr(1, 3), "PNG");
  struct stat status {};
  ASSERT_EQ(::lstat("/dev/stdout", &status), 0);
  EXPECT_TRUE(S_ISLNK(status.st_mode)) << "/dev/stdout was replaced";
}

// A process started with standard output closed gets descriptor 1 from its next open(): the
// mesh would have gone into a scratch file and been lost, with exit 0.
TEST_F(OutputTargets, AClosedStandardOutputIsRefusedNotReused) {
  // mvox is started by an inner shell with standard output closed, its errors still captured.
  const std::string closed_stdout = "sh -c '\"$0\" \"$@\" >&-'";
  test::expect_refused(dir_.path(), "extract stack -t 128 -q -o -", "standard output", "is closed",
                       1, closed_stdout);
  test::expect_refused(dir_.path(), "extract stack -t 128 -q -o m.ply --stats /dev/stdout",
                       "/dev/stdout", "standard output is closed", 1, closed_stdout);
  // A file output needs no standard output.
  const auto result = run_mvox("extract stack -t 128 -q -o m.ply", dir_.path(), closed_stdout);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_FALSE(read_ply((dir_.path() / "m.ply").string()).face_count() == 0);
}

// NAME_MAX is 255 bytes; the temporary ".NAME.XXXXXX" takes 8 more, so it is shortened.
TEST_F(OutputTargets, OutputNamesUpToTheLongestAFileSystemTakesWork) {
  for (const std::size_t length : {247u, 248u, 251u, 255u}) {
    const std::string name = std::string(length - 4, 'm') + ".ply";
    const auto result = run_mvox("extract stack -t 128 -q -o " + name, dir_.path());
    EXPECT_EQ(result.exit_code, 0) << length << ": " << result.output;
    EXPECT_TRUE(fs::exists(dir_.path() / name)) << length;
  }
}

// Links to outputs are written through: the file behind the link is replaced, the link stays.
TEST_F(OutputTargets, ALinkedOutputReplacesTheFileBehindTheLink) {
  fs::create_directory(dir_.path() / "runs");
  fs::create_symlink("runs/mesh.ply", dir_.path() / "latest.ply");
  const auto result = run_mvox("extract stack -t 128 -q -o latest.ply", dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(fs::is_symlink(dir_.path() / "latest.ply"));
  EXPECT_FALSE(read_ply((dir_.path() / "runs/mesh.ply").string()).face_count() == 0);
}

// Sets or clears a file's immutable flag (chattr +i); false where the file system or the
// process's privileges do not allow it.
bool set_immutable(const fs::path& path, bool immutable) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  int flags = 0;
  bool done = ::ioctl(fd, FS_IOC_GETFLAGS, &flags) == 0;
  if (done) {
    flags = immutable ? (flags | FS_IMMUTABLE_FL) : (flags & ~FS_IMMUTABLE_FL);
    done = ::ioctl(fd, FS_IOC_SETFLAGS, &flags) == 0;
  }
  ::close(fd);
  return done;
}

// The outputs appear together: when one cannot replace its target, none does, even those
// renamed before it would have been (the mesh is published first, the report last).
TEST_F(OutputTargets, AReportThatCannotBeReplacedKeepsTheMeshAsItWas) {
  const fs::path report = dir_.path() / "previous.json";
  if (!set_immutable(report, true))
    GTEST_SKIP() << "cannot make a file immutable here (needs root and a file system with "
                    "chattr +i, such as ext4 or xfs)";
  test::expect_refused(dir_.path(), "extract stack -t 128 -q -o previous.ply --stats previous.json",
                       "previous.json", "cannot replace file: it is immutable (chattr +i)");
  set_immutable(report, false);
}

TEST_F(OutputTargets, AnotherUsersFileInAStickyDirectoryIsRefusedBeforeAnyRename) {
  if (::geteuid() != 0 || std::system("command -v setpriv > /dev/null") != 0)
    GTEST_SKIP() << "needs root and setpriv, to own a file as one user and run mvox as another";
  // A /tmp-like directory: the report belongs to uid 65534, mvox runs as uid 65533.
  const fs::path shared = dir_.path() / "shared";
  fs::create_directory(shared);
  fs::permissions(shared, fs::perms::all | fs::perms::sticky_bit);
  fs::permissions(dir_.path(), fs::perms::all);
  write_bytes(shared / "report.json", "someone else's report\n");
  write_bytes(shared / "mesh.ply", "the previous mesh\n");
  ASSERT_EQ(::chown((shared / "report.json").c_str(), 65534, 65534), 0);
  ASSERT_EQ(::chown((shared / "mesh.ply").c_str(), 65533, 65533), 0);
  fs::permissions(shared / "report.json", fs::perms::all & ~fs::perms::owner_exec);
  test::expect_refused(dir_.path(),
                       "extract stack -t 128 -q -o shared/mesh.ply --stats shared/report.json",
                       "shared/report.json", "belongs to another user (uid 65534)", 1,
                       "setpriv --reuid=65533 --regid=65533 --clear-groups");
}

}  // namespace
}  // namespace mvox
