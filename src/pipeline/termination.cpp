#include "pipeline/termination.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>  // renameat2, RENAME_EXCHANGE (glibc 2.28)
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "message_line.h"

namespace mvox {
namespace {

// Every signal whose default action ends the process and that comes from outside: SIGQUIT is the
// terminal's quit key; SIGUSR1 and SIGXCPU are what batch schedulers send before a time limit;
// SIGALRM what some tools send. Left alone, they ended mvox with its temporaries on disk. Not
// SIGUSR2, which mvox sends its own reading threads to end a blocked read (read_cancellation.h);
// not SIGPROF or SIGVTALRM, which profilers use; not SIGABRT or SIGTRAP, which a thread raises on
// itself.
constexpr int kInterruptSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGALRM, SIGXCPU};

struct OutputRecord {
  int id = 0;
  std::string target;      // as named in messages
  std::string temporary;   // empty for direct outputs
  bool directory = false;  // the temporary is a folder, removed with what it holds
};

// Ordinary code on the interrupt thread too (termination.h): a folder's files can be removed.
void delete_temporary(const OutputRecord& record) {
  if (record.temporary.empty()) return;
  if (!record.directory) {
    ::unlink(record.temporary.c_str());
    return;
  }
  std::error_code ignored;
  std::filesystem::remove_all(record.temporary, ignored);
}

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
    case SIGQUIT: return "SIGQUIT";
    case SIGUSR1: return "SIGUSR1";
    case SIGALRM: return "SIGALRM";
    case SIGXCPU: return "SIGXCPU";
    default: return "a signal";
  }
}

std::atomic<bool> interrupts_quiet{false};

// The interrupt thread: see termination.h for why a thread and not a handler.
[[noreturn]] void wait_for_interrupt(sigset_t signals) {
  int signal_number = 0;
  while (sigwait(&signals, &signal_number) != 0) {
  }
  Registry& r = registry();
  // Held until _exit: no temporary can be created or published after this point.
  r.lock.lock();
  for (const OutputRecord& record : r.outputs) delete_temporary(record);
  const std::string& subject = r.outputs.empty() ? r.subject : r.outputs.front().target;
  // Over a progress line on a terminal, start from a clean line.
  std::string line = isatty(STDERR_FILENO) == 1 ? "\r\033[K" : "";
  line += std::string(message_program()) + ": error: " + one_line(subject) + ": interrupted by " +
          signal_name(signal_number) + "\n";
  // write(2), not stdio: another thread may hold stderr's lock for as long as it likes.
  if (!interrupts_quiet.load()) {
    const ssize_t ignored = ::write(STDERR_FILENO, line.data(), line.size());
    (void)ignored;
  }
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
    try {
      std::thread(wait_for_interrupt, signals).detach();
    } catch (const std::system_error&) {
      // No thread to take them (no memory for its stack): the signals keep their default
      // action rather than wait, blocked, for a thread that does not exist.
      pthread_sigmask(SIG_UNBLOCK, &signals, nullptr);
    }
  });
}

namespace {

// Records a temporary just created, under the registry's lock; returns its id.
int record_temporary(Registry& r, const std::string& target, const char* temporary,
                     bool directory) {
  OutputRecord record;
  record.id = r.next_id++;
  record.target = target;
  record.temporary = temporary;
  record.directory = directory;
  r.outputs.push_back(std::move(record));
  return r.outputs.back().id;
}

}  // namespace

int create_output_temporary(char* name_template, const std::string& target, int* id) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  const int fd = make_temporary(name_template);
  if (fd < 0) return -1;
  *id = record_temporary(r, target, name_template, false);
  return fd;
}

bool create_output_temporary_directory(char* name_template, const std::string& target, int* id) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  if (::mkdtemp(name_template) == nullptr) return false;
  *id = record_temporary(r, target, name_template, true);
  return true;
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

namespace {

enum class Step : unsigned char { none, exchanged, created, renamed };

// Takes back one step of publish_output_temporaries; best effort, the caller already failed.
void reverse_step(Step step, const std::string& temporary, const std::string& target) {
  switch (step) {
    case Step::exchanged:
      ::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE);
      break;
    case Step::created: ::rename(target.c_str(), temporary.c_str()); break;
    case Step::renamed:  // the previous file is gone: nothing to bring back
    case Step::none: break;
  }
}

// Puts `temporary` in place of `target`, keeping a previous target under the temporary's name.
// Returns 0 or an errno; *step says what was done.
int replace_keeping_previous(const std::string& temporary, const std::string& target, Step* step) {
  // An exchange would swap a file with a directory as readily as with a file.
  struct stat status {};
  if (::lstat(target.c_str(), &status) == 0 && S_ISDIR(status.st_mode)) return EISDIR;
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
      *step = Step::exchanged;
      return 0;
    }
    if (errno == ENOENT) {  // no previous file: create the target, replacing nothing
      if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, target.c_str(), RENAME_NOREPLACE) ==
          0) {
        *step = Step::created;
        return 0;
      }
      if (errno == EEXIST) continue;  // it appeared meanwhile: exchange with it
    }
    if (errno != EINVAL && errno != ENOSYS) return errno;
    break;  // the file system cannot exchange or refuse: a plain rename
  }
  if (::rename(temporary.c_str(), target.c_str()) != 0) return errno;
  *step = Step::renamed;
  return 0;
}

}  // namespace

int publish_output_temporaries(const std::vector<Publication>& items, std::size_t* failed_index) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  std::vector<std::string> temporaries;
  for (const Publication& item : items) {
    const auto record = std::find_if(r.outputs.begin(), r.outputs.end(),
                                     [&](const OutputRecord& o) { return o.id == item.id; });
    temporaries.push_back(record == r.outputs.end() ? std::string() : record->temporary);
  }
  std::vector<Step> steps(items.size(), Step::none);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const int error = temporaries[i].empty() ? ENOENT
                                             : replace_keeping_previous(
                                                   temporaries[i], items[i].target_path, &steps[i]);
    if (error == 0) continue;
    for (std::size_t k = i; k-- > 0;) reverse_step(steps[k], temporaries[k], items[k].target_path);
    *failed_index = i;
    return error;
  }
  // Every target is new: the previous files, kept under the temporaries' names, can go.
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (steps[i] == Step::exchanged) ::unlink(temporaries[i].c_str());
    r.outputs.erase(std::remove_if(r.outputs.begin(), r.outputs.end(),
                                   [&](const OutputRecord& o) { return o.id == items[i].id; }),
                    r.outputs.end());
  }
  return 0;
}

void discard_output(int id) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  for (auto record = r.outputs.begin(); record != r.outputs.end(); ++record) {
    if (record->id != id) continue;
    delete_temporary(*record);
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

void set_interrupts_quiet() { interrupts_quiet = true; }

void set_interrupt_subject(const std::string& subject) {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  r.subject = subject;
}

std::string interrupt_subject() {
  Registry& r = registry();
  std::lock_guard<std::recursive_mutex> hold(r.lock);
  return r.subject;
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
