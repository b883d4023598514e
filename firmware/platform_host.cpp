// The demo's platform on the host (x86-64 Linux, glibc): standard output and _exit.
#include <unistd.h>

#include <cstring>

#include "platform.h"

namespace mvox::firmware {

void console_write(const char* text) {
  std::size_t left = std::strlen(text);
  while (left > 0) {
    const ssize_t written = ::write(STDOUT_FILENO, text, left);
    if (written <= 0) return;
    text += written;
    left -= static_cast<std::size_t>(written);
  }
}

void exit_program(int status) { ::_exit(status); }

void print_target_lines() {
  console_write("target: host ");
#if defined(__x86_64__)
  console_write("x86-64");
#else
  console_write("(not x86-64)");
#endif
  console_write(", g++ " __VERSION__ ", POSIX write and _exit\n");
}

void halt(const char* message) {
  console_write("halt: ");
  console_write(message);
  console_write("\n");
  exit_program(2);
}

}  // namespace mvox::firmware
