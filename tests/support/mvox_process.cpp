#include "mvox_process.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>

namespace mvox::test {
namespace {

using Clock = std::chrono::steady_clock;

// Milliseconds left until `deadline`, at least 0.
int milliseconds_until(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  return left.count() > 0 ? static_cast<int>(left.count()) : 0;
}

}  // namespace

MvoxProcess::MvoxProcess(const std::vector<std::string>& arguments,
                         const std::filesystem::path& directory, bool own_stdout) {
  int errors[2];
  int output[2] = {-1, -1};
  if (::pipe2(errors, O_CLOEXEC) != 0 || (own_stdout && ::pipe2(output, O_CLOEXEC) != 0)) {
    ADD_FAILURE() << "pipe failed";
    return;
  }
  // Everything the child needs is prepared before fork: after it, only async-signal-safe calls.
  std::vector<std::string> words = {MVOX_BINARY};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  const std::string where = directory.string();

  pid_ = ::fork();
  if (pid_ == 0) {
    // Default dispositions and an empty mask, whatever the test runner set up.
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ})
      ::signal(signal_number, SIG_DFL);
    if (::chdir(where.c_str()) != 0) ::_exit(127);
    ::dup2(errors[1], STDERR_FILENO);
    ::dup2(own_stdout ? output[1] : errors[1], STDOUT_FILENO);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(errors[1]);
  errors_fd_ = errors[0];
  if (own_stdout) {
    ::close(output[1]);
    stdout_fd_ = output[0];
  }
  if (pid_ < 0) ADD_FAILURE() << "fork failed";
}

MvoxProcess::~MvoxProcess() {
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  close_stdout();
  if (errors_fd_ >= 0) ::close(errors_fd_);
}

void MvoxProcess::send(int signal_number) {
  ASSERT_GT(pid_, 0);
  ASSERT_EQ(::kill(pid_, signal_number), 0);
}

std::string MvoxProcess::read_stdout(std::size_t bytes) {
  std::string text;
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  while (stdout_fd_ >= 0 && text.size() < bytes) {
    pollfd ready{stdout_fd_, POLLIN, 0};
    if (::poll(&ready, 1, milliseconds_until(deadline)) <= 0) {
      ADD_FAILURE() << "no output from mvox within 30 s";
      break;
    }
    char chunk[4096];
    const std::size_t want = std::min(sizeof chunk, bytes - text.size());
    const ssize_t got = ::read(stdout_fd_, chunk, want);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    text.append(chunk, static_cast<std::size_t>(got));
  }
  return text;
}

void MvoxProcess::close_stdout() {
  if (stdout_fd_ >= 0) ::close(stdout_fd_);
  stdout_fd_ = -1;
}

MvoxProcess::Ending MvoxProcess::finish() {
  Ending ending;
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  // Standard error to its end (the process, and anything it started, has closed it)...
  while (errors_fd_ >= 0) {
    pollfd ready{errors_fd_, POLLIN, 0};
    if (::poll(&ready, 1, milliseconds_until(deadline)) <= 0) {
      ADD_FAILURE() << "mvox did not end within 60 s; killed";
      ::kill(pid_, SIGKILL);
      break;
    }
    char chunk[4096];
    const ssize_t got = ::read(errors_fd_, chunk, sizeof chunk);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    ending.errors.append(chunk, static_cast<std::size_t>(got));
  }
  // ... then its status.
  int status = 0;
  struct rusage usage {};
  if (pid_ > 0 && ::wait4(pid_, &status, 0, &usage) == pid_) {
    ending.peak_memory_kib = usage.ru_maxrss;
    if (WIFEXITED(status)) ending.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) ending.signal = WTERMSIG(status);
  }
  pid_ = -1;
  return ending;
}

}  // namespace mvox::test
