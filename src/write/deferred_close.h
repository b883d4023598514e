#pragma once
// Closing a file whose bytes are no longer wanted (a scratch file once copied into the output)
// frees its page cache, which takes milliseconds for tens of megabytes: 2.4 ms for PLY's 30 MB of
// faces from a 256x256x1024 volume. Within a DeferredCloses scope (a run that may take more
// than one thread: run_mesh_job, not `--threads 1`), that happens on a thread of its own while
// the run goes on to publish its outputs, whose replacing of an older file frees as much again;
// the scope waits for those threads when it ends. Outside one (the Python module's writers,
// mvox-mpi's parts, `--labels`), every close happens on its caller's thread.
namespace mvox {

// Files smaller than this are closed on their caller's thread: starting a thread (about 50
// microseconds here) would cost more than freeing their pages saves.
constexpr unsigned long long kDeferredCloseBytes = 16ull << 20;

class DeferredCloses {
 public:
  // `allowed` false: a scope that changes nothing (one thread for everything).
  explicit DeferredCloses(bool allowed);
  // Waits for every close handed on so far, also when the scope ends by an exception.
  ~DeferredCloses();
  DeferredCloses(const DeferredCloses&) = delete;
  DeferredCloses& operator=(const DeferredCloses&) = delete;

 private:
  bool active_;
};

// Closes `fd`, a file of `bytes` bytes, on another thread inside an allowing DeferredCloses
// scope when the file is at least kDeferredCloseBytes, else here. Its errors are not reported:
// nothing is read or written through it any more.
void close_when_unneeded(int fd, unsigned long long bytes);

}  // namespace mvox
