#pragma once
// Test support for the bad-input tests (tests/cli/bad_input_*_test.cpp): each way `mvox` can be
// given something wrong, run through the real command line. Every case checks the contract of
// README's "When things go wrong":
// - one line, "mvox: error: SUBJECT: PROBLEM", naming the file or option and the problem;
// - the exit code: 1 a failed job, 2 a usage error (plus a line pointing at --help),
//   128 + n for signal n (130 for SIGINT);
// - the directory exactly as it was: no new output, no temporary (".NAME.XXXXXX"), and the
//   previous outputs at the targets byte for byte. Most cases ask for all three outputs (mesh,
//   picture, report), created before extraction starts, so a failure mid-run must remove three
//   temporaries.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "command_runner.h"

namespace mvox::test {

// Writes into a FIFO that mvox reads, never waiting more than 30 s for mvox: a broken mvox
// must fail the test, not hang it.
class FifoWriter {
 public:
  explicit FifoWriter(const std::string& path);
  ~FifoWriter() { close(); }
  FifoWriter(const FifoWriter&) = delete;
  FifoWriter& operator=(const FifoWriter&) = delete;

  // True when every byte went in. Returns as soon as mvox has taken all but a pipe's capacity.
  bool write(const std::string& bytes);
  // Makes the pipe hold `bytes` (F_SETPIPE_SZ), so that writes that fit return at once,
  // whatever mvox does meanwhile. False when the system refuses.
  bool hold(std::size_t bytes);
  void close();

 private:
  int fd_ = -1;
};

// A directory holding an 8-bit stack of 8 slices of 12x10 in stack/ (a sphere with an inside at
// threshold 128) and a previous version of every output.
class BadInput : public ::testing::Test {
 protected:
  // Asks for every output a job can write, each where a previous version must survive.
  inline static const std::string kOutputs =
      " -o previous.ply --image previous.png --stats previous.json -q";

  void SetUp() override;

  // Runs `mvox ARGUMENTS` and checks the whole contract: one line starting
  // "mvox: error: SUBJECT" that says PROBLEM, the exit code, and nothing changed on disk: no
  // output or temporary left, the previous outputs and the inputs byte for byte as they were.
  void expect_refused(const std::string& arguments, const std::string& subject,
                      const std::string& problem, int exit_code = 1);

  // expect_refused for a job whose memory matters too: runs `mvox ARGUMENTS` without a shell
  // and returns its peak resident memory in KiB.
  long refused_peak_memory_kib(const std::vector<std::string>& arguments,
                               const std::string& subject, const std::string& problem);

  ScratchDirectory dir_;
};

}  // namespace mvox::test
