#pragma once
// What the demo program needs from where it runs: a console to print to, and a way to stop with
// a status. Two implementations, one per build: platform_semihosting.cpp for the board (QEMU's
// semihosting calls) and platform_host.cpp for the host build (POSIX).
// Nothing here allocates, and there is no printf: numbers are formatted by hand below.
#include <cstdint>

namespace mvox::firmware {

// Writes `text` as it is (no newline added).
void console_write(const char* text);

// Ends the program with `status` (0: success). On the board this exits QEMU (semihosting
// SYS_EXIT), and QEMU's own exit status tells success from failure.
[[noreturn]] void exit_program(int status);

// Prints the lines that differ by platform, each starting with "target:" (the build, and on the
// board the stack's high-water mark). The demo's script leaves them out when it compares the
// host's output with the board's.
void print_target_lines();

// Prints `message` on a line of its own after "halt: " and exits with status 2: the end of every
// trap (allocation, abort, failed assertion, CPU fault).
[[noreturn]] void halt(const char* message);

// An mvox::AssertHandler that prints the failed expression and halts (traps.cpp). The core's
// default handler calls abort(), which would end the program without a word.
[[noreturn]] void halt_on_assert(const char* expression, const char* file, int line);

inline void console_write_decimal(std::uint64_t value) {
  char digits[21];
  char* p = digits + sizeof digits;
  *--p = '\0';
  do {
    *--p = static_cast<char>('0' + value % 10);
    value /= 10;
  } while (value != 0);
  console_write(p);
}

// 0x followed by exactly 16 lower-case hex digits.
inline void console_write_hex64(std::uint64_t value) {
  char text[19] = "0x";
  for (int i = 0; i < 16; ++i) text[2 + i] = "0123456789abcdef"[(value >> (60 - 4 * i)) & 0xf];
  text[18] = '\0';
  console_write(text);
}

}  // namespace mvox::firmware
