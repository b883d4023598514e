#pragma once
// Closing a file whose bytes are no longer wanted (a scratch file once copied into the output)
// frees its page cache, which takes milliseconds for tens of megabytes: 2.4 ms for PLY's 30 MB of
// faces from a 256x256x1024 volume. Unless a run must take one thread (`--threads 1`), that
// happens on a thread of its own while the run goes on to publish its outputs, whose replacing
// of an older file frees as much again.
namespace mvox {

// Whether closes may be handed to another thread; off, every close happens on its caller's
// thread. On by default.
void allow_deferred_closes(bool allowed);

// Files smaller than this are closed on their caller's thread: starting a thread (about 50
// microseconds here) would cost more than freeing their pages saves.
constexpr unsigned long long kDeferredCloseBytes = 16ull << 20;

// Closes `fd`, a file of `bytes` bytes, on another thread when allowed and the file is at least
// kDeferredCloseBytes, else here. Its errors are not reported: nothing is read or written
// through it any more.
void close_when_unneeded(int fd, unsigned long long bytes);

// Waits for every close handed on so far. A run calls it once its outputs are published; the
// process also waits at exit.
void finish_deferred_closes();

}  // namespace mvox
