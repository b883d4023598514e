#include "termination.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "message_line.h"

namespace mvox {
namespace {

constexpr int kInterruptSignals[] = {SIGINT, SIGTERM, SIGHUP};

struct OutputRecord {
  int id = 0;
  std::string target;     // as named in messages
  std::string temporary;  // empty for direct outputs
};

// Recursive so that an InterruptsDeferred scope can publish files, which lock again.
struct Registry {
  std::recursive_mutex lock;
  std::vector<OutputRecord> outputs;  // in creation order: the first is the job's main output
  std::string subject = "mvox";
  int next_id = 1;
};

// Never destroyed: the signal thread may still use it while static destructors run at exit.
Registry& registry() {
  static Registry* const instance = new Registry;
  return *instance;
}

std::atomic<bool> broken_pipe{false};

const char* signal_name(int signal_number) {
  switch (signal_number) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "a signal";
  }
}

// The interrupt thread: see termination.h for why a thread and not a handler.
[[noreturn]] void wait_for_interrupt(sigset_t signals) {
  int signal_number = 0;
  while (sigwait(&signals, &signal_number) != 0) {
  }
  Registry& r = registry();
  // Held until _exit: no temporary can be created or published after this point.
  r.lock.lock();
  for (const OutputRecord& record : r.outputs)
    if (!record.temporary.empty()) ::unlink(record.temporary.c_str());
  const std::string& subject = r.outputs.empty() ? r.subject : r.outputs.front().target;
  // Over a progress line on a terminal, start from a clean line.
  std::string line = isatty(STDERR_FILENO) == 1 ? "\r\033[K" : "";
  line +=
      "mvox: error: " + one_line(subject) + ": interrupted by " + signal_name(signal_number) + "\n";
  // write(2), not stdio: another thread may hold stderr's lock for as long as it likes.
  const ssize_t ignored = ::write(STDERR_FILENO, line.data(), line.size());
  (void)ignored;
  ::_exit(128 + signal_number);
}

int make_temporary(char* name_template) { return ::mkostemp(name_template, O_CLOEXEC); }

}  // namespace

void install_termination_handling() {
  static std::once_flag installed;
  std::call_once(installed, [] {
    ::signal(SIGPIPE, SIG_IGN);
    // A file-size limit (ulimit -f) would kill mvox with its temporaries left behind; ignored,
    // the write fails with EFBIG and is reported like a full disk.
    ::signal(SIGXFSZ, SIG_IGN);
    sigset_t signals;
    sigemptyset(&signals);
    for (const int signal_number : kInterruptSignals) {
      struct sigaction current {};
      if (::sigaction(signal_number, nullptr, &current) == 0 && current.sa_handler == SIG_IGN)
        continue;
      sigaddset(&signals, signal_number);
    }
    if (pthread_sigmask(SIG_BLOCK, &signals, nullptr) != 0) return;
    std::thread(wait_for_interrupt, signals).detach();
  });
}

int create_output_temporary(char* name_template, const std::string& target, int* id) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  const int fd = make_temporary(name_template);
  if (fd < 0) return -1;
  OutputRecord record;
  record.id = r.next_id++;
  record.target = target;
  record.temporary = name_template;
  r.outputs.push_back(std::move(record));
  *id = r.outputs.back().id;
  return fd;
}

int register_direct_output(const std::string& target) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  OutputRecord record;
  record.id = r.next_id++;
  record.target = target;
  r.outputs.push_back(std::move(record));
  return r.outputs.back().id;
}

int publish_output_temporary(int id, const std::string& target_path) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  for (auto record = r.outputs.begin(); record != r.outputs.end(); ++record) {
    if (record->id != id) continue;
    if (::rename(record->temporary.c_str(), target_path.c_str()) != 0) return errno;
    r.outputs.erase(record);
    return 0;
  }
  return ENOENT;
}

void discard_output(int id) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  for (auto record = r.outputs.begin(); record != r.outputs.end(); ++record) {
    if (record->id != id) continue;
    if (!record->temporary.empty()) ::unlink(record->temporary.c_str());
    r.outputs.erase(record);
    return;
  }
}

int create_nameless_temporary(char* name_template) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  const int fd = make_temporary(name_template);
  if (fd >= 0) ::unlink(name_template);
  return fd;
}

void set_interrupt_subject(const std::string& subject) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  r.subject = subject;
}

InterruptsDeferred::InterruptsDeferred() { registry().lock.lock(); }
InterruptsDeferred::~InterruptsDeferred() { registry().lock.unlock(); }

void note_broken_pipe() { broken_pipe = true; }
bool broken_pipe_noted() { return broken_pipe; }

void exit_for_broken_pipe() {
  std::fflush(nullptr);
  ::signal(SIGPIPE, SIG_DFL);
  sigset_t pipe_signal;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_UNBLOCK, &pipe_signal, nullptr);
  ::raise(SIGPIPE);
  ::_exit(128 + SIGPIPE);  // not reached unless SIGPIPE is somehow held back
}

}  // namespace mvox
