// OutputFile and the publishing of several outputs together (src/write/output_file.h,
// src/pipeline/termination.h): a file appears only at its commit, with its writes in order, or
// not at all, keeping the previous one; errors name the target (a missing directory, a directory,
// a full device or standard output); and several outputs are published all or none, even when a
// rename fails after another succeeded.
#include "write/output_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error.h"
#include "file_io.h"
#include "pipeline/termination.h"
#include "stdout_redirect.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::exists;
using test::read_bytes;
using test::write_bytes;

using test::ScratchDirectory;

// A temporary of the output registry holding `bytes`, as OutputFile makes them.
int make_temporary(const fs::path& directory, const std::string& bytes) {
  std::string name = (directory / ".output.XXXXXX").string();
  int id = 0;
  const int fd = create_output_temporary(name.data(), "output", &id);
  EXPECT_GE(fd, 0);
  EXPECT_EQ(::write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  ::close(fd);
  return id;
}

std::size_t hidden_files(const fs::path& directory) {
  std::size_t count = 0;
  for (const auto& entry : fs::directory_iterator(directory))
    count += entry.path().filename().string().front() == '.';
  return count;
}

TEST(OutputPublication, ReplacesEveryTargetAndDeletesThePreviousFiles) {
  ScratchDirectory dir;
  write_bytes(dir.path() / "a", "old a");
  const std::vector<Publication> items = {{make_temporary(dir.path(), "new a"), dir / "a"},
                                          {make_temporary(dir.path(), "new b"), dir / "b"}};
  std::size_t failed = 99;
  EXPECT_EQ(publish_output_temporaries(items, &failed), 0);
  EXPECT_EQ(read_bytes(dir.path() / "a"), "new a");
  EXPECT_EQ(read_bytes(dir.path() / "b"), "new b");
  EXPECT_EQ(hidden_files(dir.path()), 0u) << dir.listing();
}

// The third target cannot be replaced (it has become a directory, or its directory has gone):
// the first two, already replaced or created, are brought back.
TEST(OutputPublication, AFailedRenameUndoesTheOnesBeforeIt) {
  for (const char* third : {"c", "gone/c"}) {
    SCOPED_TRACE(third);
    ScratchDirectory dir;
    write_bytes(dir.path() / "a", "old a");
    fs::create_directories(dir.path() / "c/inside");
    const std::vector<Publication> items = {{make_temporary(dir.path(), "new a"), dir / "a"},
                                            {make_temporary(dir.path(), "new b"), dir / "b"},
                                            {make_temporary(dir.path(), "new c"), dir / third}};
    std::size_t failed = 99;
    EXPECT_NE(publish_output_temporaries(items, &failed), 0);
    EXPECT_EQ(failed, 2u);
    EXPECT_EQ(read_bytes(dir.path() / "a"), "old a");
    EXPECT_FALSE(fs::exists(dir.path() / "b"));
    EXPECT_TRUE(fs::is_directory(dir.path() / "c/inside"));
    // The temporaries are still recorded, holding the new bytes; discarding deletes them.
    EXPECT_EQ(hidden_files(dir.path()), 3u) << dir.listing();
    for (const Publication& item : items) discard_output(item.id);
    EXPECT_EQ(hidden_files(dir.path()), 0u) << dir.listing();
  }
}

// OutputFile's own check, before any rename: an immutable target stops all of them.
TEST(OutputPublication, PublishTogetherChecksEveryTargetFirst) {
  ScratchDirectory dir;
  write_bytes(dir.path() / "mesh.ply", "old mesh");
  write_bytes(dir.path() / "report.json", "old report");
  const int fd = ::open((dir.path() / "report.json").c_str(), O_RDONLY | O_CLOEXEC);
  int flags = 0;
  const bool immutable = fd >= 0 && ::ioctl(fd, FS_IOC_GETFLAGS, &flags) == 0 &&
                         (flags |= FS_IMMUTABLE_FL, ::ioctl(fd, FS_IOC_SETFLAGS, &flags) == 0);
  if (!immutable) {
    if (fd >= 0) ::close(fd);
    GTEST_SKIP() << "cannot make a file immutable here (needs root and chattr +i support)";
  }
  {
    OutputFile mesh(dir / "mesh.ply");
    OutputFile report(dir / "report.json");
    mesh.write("new mesh", 8);
    report.write("new report", 10);
    mesh.seal();
    report.seal();
    try {
      publish_together({&mesh, &report});
      ADD_FAILURE() << "an immutable target was replaced";
    } catch (const Error& error) {
      EXPECT_EQ(error.subject(), dir / "report.json");
      EXPECT_NE(error.problem().find("immutable"), std::string::npos) << error.what();
    }
  }
  flags &= ~FS_IMMUTABLE_FL;
  ::ioctl(fd, FS_IOC_SETFLAGS, &flags);
  ::close(fd);
  EXPECT_EQ(read_bytes(dir.path() / "mesh.ply"), "old mesh");
  EXPECT_EQ(read_bytes(dir.path() / "report.json"), "old report");
  EXPECT_EQ(hidden_files(dir.path()), 0u) << dir.listing();
}

TEST(OutputFile, AppearsOnlyAtCommit) {
  ScratchDirectory dir;
  const std::string target = dir.file("out.bin");
  {
    OutputFile out(target);
    out.write("hello world", 11);
    EXPECT_TRUE(out.can_overwrite());
    EXPECT_FALSE(exists(target));
    ASSERT_EQ(dir.entries().size(), 1u);
    EXPECT_EQ(dir.entries()[0].rfind(".out.bin.", 0), 0u) << dir.entries()[0];
    out.overwrite(6, "W", 1);
    EXPECT_EQ(out.bytes_written(), 11u);
    out.commit();
  }
  EXPECT_EQ(read_bytes(target), "hello World");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(OutputFile, WritesLargerThanTheBufferArriveInOrder) {
  ScratchDirectory dir;
  std::string expected;
  {
    OutputFile out(dir.file("big.bin"));
    for (int round = 0; round < 3; ++round) {
      // Small writes that straddle the buffer, then one block larger than the buffer.
      for (int i = 0; i < 70000; ++i) {
        const std::string piece = std::to_string(i) + ",";
        out.write(piece.data(), piece.size());
        expected += piece;
      }
      const std::string block(BufferedWriter::kBufferBytes + 17, static_cast<char>('a' + round));
      out.write(block.data(), block.size());
      expected += block;
    }
    out.overwrite(1, "#", 1);
    expected[1] = '#';
    out.commit();
  }
  EXPECT_EQ(read_bytes(dir.file("big.bin")), expected);
}

// Blocks are allocated ahead of the writes (BufferedWriter::set_fd), and what is left past the
// end is freed when the file is sealed: the published file takes no more room than its bytes.
TEST(OutputFile, BlocksAllocatedAheadAreFreedWhenTheFileIsSealed) {
  ScratchDirectory dir;
  // Does this file system allocate ahead at all? (ext4 and XFS do; some do not.)
  const int probe = ::open(dir.file("probe").c_str(), O_CREAT | O_WRONLY, 0600);
  ASSERT_GE(probe, 0);
  const bool allocates_ahead = ::fallocate(probe, FALLOC_FL_KEEP_SIZE, 0, 1 << 20) == 0;
  ::close(probe);
  std::filesystem::remove(dir.file("probe"));

  const std::string target = dir.file("big.bin");
  const std::string block(1 << 20, 'x');
  constexpr std::uint64_t kBytes = (std::uint64_t{9} << 20) + 1;  // allocated ahead to 16 MiB
  auto allocated_bytes = [](const std::string& path) {
    struct stat status {};
    EXPECT_EQ(::stat(path.c_str(), &status), 0) << path;
    return std::uint64_t(status.st_blocks) * 512;
  };
  {
    OutputFile out(target);
    for (int i = 0; i < 9; ++i) out.write(block.data(), block.size());
    out.write("y", 1);
    out.overwrite(0, "x", 1);  // the same byte again: flushes what is buffered
    ASSERT_EQ(dir.entries().size(), 1u);
    const std::string temporary = dir.file(dir.entries()[0]);
    if (allocates_ahead) EXPECT_GE(allocated_bytes(temporary), kBytes + (std::uint64_t{4} << 20));
    out.commit();
  }
  EXPECT_EQ(std::filesystem::file_size(target), kBytes);
  EXPECT_LT(allocated_bytes(target), kBytes + (std::uint64_t{1} << 20));
}

TEST(OutputFile, DestructorWithoutCommitLeavesNothingAndKeepsThePreviousFile) {
  ScratchDirectory dir;
  const std::string target = dir.file("keep.txt");
  write_bytes(target, "previous");
  {
    OutputFile out(target);
    out.write("new", 3);
  }
  EXPECT_EQ(read_bytes(target), "previous");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"keep.txt"});
}

TEST(OutputFile, MissingDirectoryNamesTheTarget) {
  ScratchDirectory dir;
  const std::string target = dir.file("no/such/dir/mesh.ply");
  try {
    OutputFile out(target);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              target + ": cannot create file: No such file or directory");
    EXPECT_EQ(error.subject(), target);
  }
}

TEST(OutputFile, DirectoryTargetIsRefused) {
  ScratchDirectory dir;
  EXPECT_THROW(OutputFile out(dir.file("")), Error);
  try {
    OutputFile out(::testing::TempDir());
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("Is a directory"), std::string::npos);
  }
}

TEST(OutputFile, FullDeviceIsReported) {
  if (!exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  try {
    // A device is written directly (renaming onto it would replace the device node).
    OutputFile out("/dev/full");
    EXPECT_FALSE(out.can_overwrite());
    out.write("x", 1);
    out.commit();
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "/dev/full: write failed: No space left on device");
  }
  struct stat status {};
  ASSERT_EQ(::stat("/dev/full", &status), 0);
  EXPECT_TRUE(S_ISCHR(status.st_mode)) << "/dev/full was replaced";
}

TEST(OutputFile, StandardOutputFullIsReported) {
  if (!exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  std::string message;
  {
    test::StdoutRedirect redirect("/dev/full");
    try {
      OutputFile out("-");
      out.write("x", 1);
      out.commit();
    } catch (const Error& error) {
      message = error.what();
    }
  }
  EXPECT_EQ(message, "standard output: write failed: No space left on device");
}

TEST(OutputFile, ATargetNameOfTheLongestLengthGetsAShortenedTemporary) {
  ScratchDirectory dir;
  const std::string name(255, 'n');
  OutputFile file(dir / name);
  file.write("bytes", 5);
  file.commit();
  EXPECT_EQ(read_bytes(dir.path() / name), "bytes");
}

// Under /dev nothing is ever created: a name there that does not exist is an error.
TEST(OutputFile, NothingIsCreatedUnderDev) {
  try {
    OutputFile file("/dev/mvox_no_such_device");
    ADD_FAILURE() << "a file was created under /dev";
    std::error_code ignored;
    fs::remove("/dev/mvox_no_such_device", ignored);
  } catch (const Error& error) {
    EXPECT_NE(error.problem().find("never creates"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace mvox
