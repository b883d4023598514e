#pragma once
// Lets one thread make another give up a read that blocks. A reader of a pipe or FIFO (RawFile
// on /dev/stdin) can wait in read() for as long as the writer keeps the pipe open; when the job
// has already failed, the thread that joins the reader would wait with it. Closing the
// descriptor does not wake a blocked read(), and a flag is only looked at between reads, so the
// waker also interrupts the blocked call with a signal (SIGUSR2, whose handler does nothing and
// is installed without SA_RESTART), and the read loop, seeing EINTR with the flag set, stops.
#include <atomic>
#include <thread>

namespace mvox {

// Called once in the reading thread: its reads stop when `*cancelled` is true.
void set_reads_cancelled_by(const std::atomic<bool>* cancelled);

// In a read loop, after EINTR: true when this thread has been told to stop reading.
bool reads_cancelled();

// Interrupts whatever blocking call `thread` is in (it returns EINTR); the first call installs
// the do-nothing SIGUSR2 handler. Harmless when the thread is not blocked; repeat until the thread
// has stopped, since the signal may land just before it enters the call.
void wake_blocked_read(std::thread& thread);

}  // namespace mvox
