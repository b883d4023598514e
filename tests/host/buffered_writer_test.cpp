// BufferedWriter (src/write/buffered_writer.h): bytes arrive in the order they were appended
// whatever mix of small writes, records formatted in place, blocks larger than the buffer and
// appended files carries them, including once full buffers go to the writing thread; and an
// error of a background write is returned by a later call, never lost.
#include "write/buffered_writer.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "command_runner.h"
#include "file_io.h"

namespace mvox {
namespace {

constexpr std::size_t kBuffer = BufferedWriter::kBufferBytes;

// Deterministic bytes that differ at every offset, so that a reordered block shows.
std::vector<unsigned char> pattern(std::size_t size, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<unsigned char> bytes(size);
  for (auto& b : bytes) b = static_cast<unsigned char>(random());
  return bytes;
}

TEST(BufferedWriter, EveryWayOfAppendingKeepsTheOrderAcrossBackgroundWrites) {
  test::ScratchDirectory dir;
  const std::string path = dir / "out.bin";
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  const std::string spooled_path = dir / "spool.bin";
  const std::vector<unsigned char> spooled = pattern(3 * kBuffer + 17, 9);
  test::write_bytes(spooled_path, spooled);
  const int spool = ::open(spooled_path.c_str(), O_RDONLY);
  ASSERT_GE(spool, 0);

  std::vector<unsigned char> expected;
  {
    BufferedWriter writer;
    writer.set_fd(fd);
    const std::vector<unsigned char> source = pattern(12 * kBuffer, 1);
    std::size_t at = 0;
    std::mt19937 random(2);
    // Several buffers' worth of each kind, so that the writing thread takes many of them.
    for (int round = 0; round < 40; ++round) {
      const int kind = static_cast<int>(random() % 4);
      if (kind == 0) {  // small writes
        for (int i = 0; i < 1000; ++i) {
          const std::size_t size = random() % 29 + 1;
          ASSERT_EQ(writer.write(source.data() + at, size), 0);
          expected.insert(expected.end(), source.begin() + at, source.begin() + at + size);
          at = (at + size) % (source.size() - kBuffer * 2);
        }
      } else if (kind == 1) {  // records formatted in place
        const std::size_t size = random() % kBuffer + 1;
        int error = 0;
        char* room = writer.reserve(size, &error);
        ASSERT_NE(room, nullptr) << error;
        std::copy(source.begin() + at, source.begin() + at + size, room);
        writer.commit(size);
        expected.insert(expected.end(), source.begin() + at, source.begin() + at + size);
        at = (at + size) % (source.size() - kBuffer * 2);
      } else if (kind == 2) {  // a block larger than the buffer
        const std::size_t size = kBuffer + random() % kBuffer;
        ASSERT_EQ(writer.write(source.data() + at, size), 0);
        expected.insert(expected.end(), source.begin() + at, source.begin() + at + size);
        at = (at + size) % (source.size() - kBuffer * 2);
      } else if (round % 8 == 3) {  // a scratch file appended by the kernel
        bool short_source = true;
        ASSERT_EQ(writer.append_file(spool, spooled.size(), &short_source), 0);
        EXPECT_FALSE(short_source);
        expected.insert(expected.end(), spooled.begin(), spooled.end());
      }
    }
    ASSERT_EQ(writer.flush(), 0);
    EXPECT_EQ(writer.bytes_written(), expected.size());
    writer.set_fd(-1);
  }
  ::close(fd);
  ::close(spool);
  const std::string written = test::read_bytes(path);
  ASSERT_EQ(written.size(), expected.size());
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(),
                         reinterpret_cast<const unsigned char*>(written.data())))
      << "the bytes arrived out of order";
}

enum class Ahead { no, yes };               // blocks allocated ahead, released at the end
enum class Source { whole, short_by_100 };  // what append_file finds in the source

// Through one writer into `fd`: `head`, then `size` bytes of the file `spool` appended.
void append_after(const std::string& head, int fd, int spool, std::uint64_t size, Ahead ahead,
                  Source source) {
  BufferedWriter writer;
  writer.set_fd(fd, ahead == Ahead::yes);
  ASSERT_EQ(writer.write(head.data(), head.size()), 0);  // in the buffer: flushed first
  bool short_source = source == Source::whole;
  ASSERT_EQ(writer.append_file(spool, size, &short_source), 0);
  EXPECT_EQ(short_source, source == Source::short_by_100);
  const std::uint64_t appended = source == Source::whole ? size : size - 100;
  EXPECT_EQ(writer.bytes_written(), head.size() + appended);
  ASSERT_EQ(writer.flush(), 0);
  if (ahead == Ahead::yes) ASSERT_EQ(writer.release_allocation(), 0);
  writer.set_fd(-1);
}

TEST(BufferedWriter, AnAppendedFileReachesFilesAndPipesAndAShortOneIsNoted) {
  test::ScratchDirectory dir;
  const std::vector<unsigned char> spooled = pattern(2 * kBuffer + 12345, 4);
  test::write_bytes(dir / "spool.bin", spooled);
  const int spool = ::open((dir / "spool.bin").c_str(), O_RDONLY);
  ASSERT_GE(spool, 0);
  const std::string head = "head";
  const std::string expected =
      head + std::string(reinterpret_cast<const char*>(spooled.data()), spooled.size());

  // A regular file (spliced through a pipe), asked for more than the source holds.
  const int fd = ::open((dir / "out.bin").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  append_after(head, fd, spool, spooled.size() + 100, Ahead::no, Source::short_by_100);
  ::close(fd);
  EXPECT_TRUE(test::read_bytes(dir / "out.bin") == expected) << "spliced bytes differ";

  // Blocks allocated ahead of the writes, then released: the file ends at its last byte.
  const int allocated = ::open((dir / "ahead.bin").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(allocated, 0);
  append_after(head, allocated, spool, spooled.size(), Ahead::yes, Source::whole);
  ::close(allocated);
  EXPECT_TRUE(test::read_bytes(dir / "ahead.bin") == expected) << "allocated-ahead bytes differ";

  // A file opened to append (`mvox ... -o - >> mesh.ply`) takes no splice, found when the pipe
  // already holds a chunk: that chunk is read from the source again, another way.
  test::write_bytes(dir / "appended.bin", std::string("x"));
  const int appended = ::open((dir / "appended.bin").c_str(), O_WRONLY | O_APPEND);
  ASSERT_GE(appended, 0);
  append_after(head, appended, spool, spooled.size(), Ahead::no, Source::whole);
  ::close(appended);
  EXPECT_TRUE(test::read_bytes(dir / "appended.bin") == "x" + expected) << "appended bytes differ";

  // A pipe, which is no regular file: copied another way, in order.
  int ends[2];
  ASSERT_EQ(::pipe(ends), 0);
  std::string piped;
  std::thread reader([&] {
    char block[65536];
    for (ssize_t n; (n = ::read(ends[0], block, sizeof block)) > 0;) piped.append(block, n);
  });
  append_after(head, ends[1], spool, spooled.size(), Ahead::no, Source::whole);
  ::close(ends[1]);
  reader.join();
  ::close(ends[0]);
  ::close(spool);
  EXPECT_TRUE(piped == expected) << "piped bytes differ";
}

TEST(BufferedWriter, ABackgroundWriteErrorIsReturnedByALaterCall) {
  const int fd = ::open("/dev/full", O_WRONLY);
  ASSERT_GE(fd, 0);
  BufferedWriter writer;
  writer.set_fd(fd);
  const std::vector<unsigned char> bytes = pattern(kBuffer / 4, 3);
  int error = 0;
  // The first full buffers go to the writing thread, which finds the device full.
  for (int i = 0; i < 64 && error == 0; ++i) error = writer.write(bytes.data(), bytes.size());
  if (error == 0) error = writer.flush();
  EXPECT_EQ(error, ENOSPC);
  writer.set_fd(-1);
  ::close(fd);
}

// Blocks are allocated ahead on a file system that has them, never on tmpfs, where fallocate
// would take and zero-fill memory the writes then fill again (/tmp is tmpfs on many systems).
TEST(BufferedWriter, AllocatesAheadExceptOnTmpfs) {
  constexpr long kTmpfsMagic = 0x01021994;
  auto on_tmpfs = [](int fd) {
    struct statfs info {};
    return ::fstatfs(fd, &info) == 0 && static_cast<long>(info.f_type) == kTmpfsMagic;
  };
  test::ScratchDirectory dir;
  {
    const int fd = ::open((dir.path() / "here.bin").c_str(), O_RDWR | O_CREAT | O_TRUNC, 0600);
    ASSERT_GE(fd, 0);
    BufferedWriter writer;
    writer.set_fd(fd, true);
    EXPECT_EQ(writer.allocates_ahead(), !on_tmpfs(fd));
    writer.set_fd(-1);
    ::close(fd);
  }
  struct statfs shm {};
  if (::statfs("/dev/shm", &shm) != 0 || static_cast<long>(shm.f_type) != kTmpfsMagic)
    GTEST_SKIP() << "no tmpfs at /dev/shm to write into";
  const std::string path = "/dev/shm/mvox_buffered_writer_test." + std::to_string(::getpid());
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC, 0600);
  ASSERT_GE(fd, 0);
  ::unlink(path.c_str());
  BufferedWriter writer;
  writer.set_fd(fd, true);
  EXPECT_FALSE(writer.allocates_ahead());
  const char byte = 'x';
  ASSERT_EQ(writer.write(&byte, 1), 0);
  ASSERT_EQ(writer.flush(), 0);
  struct stat status {};
  ASSERT_EQ(::fstat(fd, &status), 0);
  EXPECT_LE(status.st_blocks * 512, 64 * 1024) << "memory taken ahead on tmpfs";
  writer.set_fd(-1);
  ::close(fd);
}

}  // namespace
}  // namespace mvox
