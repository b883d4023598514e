// --sync: every output is made durable (fsync) before it is renamed over its target; without
// it no output is synced, as cp and VTK write (a power loss may then leave an empty file; any
// other process still sees the old file or the whole new one). Checked with strace on the
// system calls mvox makes, and the files are the same bytes either way.
#include <gtest/gtest.h>

#include <string>

#include "support/command_runner.h"
#include "support/file_io.h"

namespace mvox {
namespace {

using test::run_mvox;

// The fsync and rename calls of `arguments`, in order, as strace writes them.
std::string sync_and_rename_calls(const std::string& arguments, const test::ScratchDirectory& dir) {
  const test::CommandResult result = run_mvox(
      arguments, dir.path(), "strace -f -qq -e trace=fsync,rename,renameat,renameat2 -o calls.txt");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  return test::read_bytes(dir.path() / "calls.txt");
}

TEST(OutputSync, WithSyncEveryOutputIsSyncedBeforeItsRename) {
  test::ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 16x16x8 -q", dir.path()).exit_code, 0);
  const std::string outputs = " -o m.ply --image p.png --stats s.json -q";
  const std::string plain = sync_and_rename_calls("extract stack -t 100" + outputs, dir);
  EXPECT_EQ(plain.find("fsync("), std::string::npos) << plain;
  EXPECT_NE(plain.find("rename"), std::string::npos) << "strace saw no rename:\n" << plain;
  const std::string mesh = test::read_bytes(dir.path() / "m.ply");
  const std::string picture = test::read_bytes(dir.path() / "p.png");

  const std::string synced = sync_and_rename_calls("extract stack -t 100 --sync" + outputs, dir);
  // Three outputs: three fsyncs, all before the first rename (they are published together).
  std::size_t fsyncs = 0, at = 0;
  while ((at = synced.find("fsync(", at)) != std::string::npos) ++fsyncs, ++at;
  EXPECT_EQ(fsyncs, 3u) << synced;
  EXPECT_LT(synced.rfind("fsync("), synced.find("rename")) << synced;
  EXPECT_EQ(test::read_bytes(dir.path() / "m.ply"), mesh);
  EXPECT_EQ(test::read_bytes(dir.path() / "p.png"), picture);
}

}  // namespace
}  // namespace mvox
