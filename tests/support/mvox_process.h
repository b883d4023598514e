#pragma once
// Test support: mvox as a running process the test can talk to while it runs: send it signals,
// read its standard output a little and close the pipe. Unlike run_mvox (command_runner.h)
// there is no shell in between, so a signal reaches mvox itself, and none is ignored (a shell
// ignores SIGINT for background jobs).
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace mvox::test {

class MvoxProcess {
 public:
  // Starts `mvox ARGUMENTS...` in `directory`. Standard error goes to a pipe that finish()
  // reads; standard output goes there too unless `own_stdout`, in which case it is a pipe of
  // its own that the test reads with read_stdout() and may close early.
  MvoxProcess(const std::vector<std::string>& arguments, const std::filesystem::path& directory,
              bool own_stdout = false);
  ~MvoxProcess();  // kills and reaps the process if finish() was not called
  MvoxProcess(const MvoxProcess&) = delete;
  MvoxProcess& operator=(const MvoxProcess&) = delete;

  pid_t pid() const { return pid_; }
  void send(int signal_number);

  // Up to `bytes` bytes of standard output (fewer at its end); waits at most 30 s.
  std::string read_stdout(std::size_t bytes);
  void close_stdout();  // what `head -c N` does once it has its bytes

  struct Ending {
    int exit_code = -1;        // when it exited
    int signal = 0;            // when it was killed by a signal
    std::string errors;        // standard error (and standard output unless own_stdout)
    long peak_memory_kib = 0;  // mvox's peak resident memory (its ru_maxrss), in KiB
  };
  // Waits for the end, reading standard error meanwhile; after 60 s the process is killed and
  // the test fails.
  Ending finish();

 private:
  pid_t pid_ = -1;
  int errors_fd_ = -1;
  int stdout_fd_ = -1;
};

}  // namespace mvox::test
