#include "bad_input.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <thread>

#include "file_io.h"
#include "mvox_process.h"
#include "refusal.h"

namespace mvox::test {

namespace {

// The outputs of kOutputs, each with a previous version that must survive.
const char* const kPreviousOutputs[] = {"previous.ply", "previous.png", "previous.json"};

}  // namespace

FifoWriter::FifoWriter(const std::string& path) {
  // Writing to a FIFO whose reader has gone raises SIGPIPE, which would end the test binary.
  ::signal(SIGPIPE, SIG_IGN);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  // O_NONBLOCK: the open fails with ENXIO until mvox has the FIFO open for reading.
  while ((fd_ = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC)) < 0 && errno == ENXIO &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (fd_ < 0) ADD_FAILURE() << path << ": mvox did not open the FIFO within 30 s";
}

bool FifoWriter::write(const std::string& bytes) {
  std::size_t done = 0;
  while (fd_ >= 0 && done < bytes.size()) {
    pollfd ready{fd_, POLLOUT, 0};
    if (::poll(&ready, 1, 30000) <= 0) return false;
    const ssize_t put = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (put < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (put < 0) return false;
    done += static_cast<std::size_t>(put);
  }
  return done == bytes.size();
}

bool FifoWriter::hold(std::size_t bytes) {
  return fd_ >= 0 && ::fcntl(fd_, F_SETPIPE_SZ, static_cast<int>(bytes)) >= static_cast<int>(bytes);
}

void FifoWriter::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void BadInput::SetUp() {
  // An 8-bit stack of 8 slices of 12x10: a sphere with an inside at threshold 128.
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 12x10x8 -q", dir_.path()).exit_code, 0);
  for (const char* name : kPreviousOutputs)
    write_bytes(dir_ / name, std::string("the previous ") + name + ", which must survive\n");
}

void BadInput::expect_refused(const std::string& arguments, const std::string& subject,
                              const std::string& problem, int exit_code) {
  test::expect_refused(dir_.path(), arguments, subject, problem, exit_code);
}

long BadInput::refused_peak_memory_kib(const std::vector<std::string>& arguments,
                                       const std::string& subject, const std::string& problem) {
  const auto before = test::tree_snapshot(dir_.path());
  MvoxProcess mvox(arguments, dir_.path());
  const MvoxProcess::Ending ending = mvox.finish();
  test::expect_one_line_error({ending.exit_code, ending.errors}, subject);
  EXPECT_EQ(ending.errors.rfind("mvox: error: " + subject, 0), 0u) << ending.errors;
  EXPECT_NE(ending.errors.find(problem), std::string::npos)
      << "expected \"" << problem << "\" in: " << ending.errors;
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
  return ending.peak_memory_kib;
}

}  // namespace mvox::test
