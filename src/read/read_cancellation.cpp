#include "read/read_cancellation.h"

#include <pthread.h>
#include <signal.h>

#include <mutex>

namespace mvox {
namespace {

thread_local const std::atomic<bool>* t_cancelled = nullptr;

extern "C" void ignore_wakeup(int) {}

}  // namespace

void set_reads_cancelled_by(const std::atomic<bool>* cancelled) { t_cancelled = cancelled; }

bool reads_cancelled() { return t_cancelled && t_cancelled->load(); }

void wake_blocked_read(std::thread& thread) {
  static std::once_flag installed;
  std::call_once(installed, [] {
    struct sigaction action = {};
    action.sa_handler = ignore_wakeup;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;  // no SA_RESTART: the blocked read must return EINTR
    sigaction(SIGUSR2, &action, nullptr);
  });
  pthread_kill(thread.native_handle(), SIGUSR2);
}

}  // namespace mvox
