// The demo's platform on the board: output and exit through ARM semihosting. The debugger (here
// QEMU, run with -semihosting-config enable=on,target=native) serves the requests the program
// makes with `bkpt 0xab`: SYS_WRITE0 prints a string on QEMU's console, SYS_EXIT_EXTENDED ends
// QEMU with the program's status as its own.
//
// The semihosting calls are made here rather than through newlib's librdimon
// (--specs=rdimon.specs): its initialise_monitor_handles() sets up newlib's stdio, which in
// newlib-nano takes its FILE structures from malloc, and the trapping allocator (traps.cpp)
// stops it there. Nothing else of newlib's system layer is needed: the image links no syscalls.
#include <cstddef>
#include <cstdint>

#include "platform.h"

namespace mvox::firmware {

// Defined in startup_cortex_m.cpp.
std::size_t stack_bytes_used();
std::size_t stack_bytes_reserved();

namespace {

// Semihosting operation numbers (ARM's "Semihosting for AArch32 and AArch64").
constexpr std::uintptr_t kSysWrite0 = 0x04;           // r1: a NUL-terminated string
constexpr std::uintptr_t kSysExitExtended = 0x20;     // r1: {reason, exit status}
constexpr std::uintptr_t kApplicationExit = 0x20026;  // ADP_Stopped_ApplicationExit

std::uintptr_t semihosting_call(std::uintptr_t operation, const void* argument) {
  register std::uintptr_t r0 __asm__("r0") = operation;
  register const void* r1 __asm__("r1") = argument;
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

}  // namespace

void console_write(const char* text) { semihosting_call(kSysWrite0, text); }

void exit_program(int status) {
  const std::uintptr_t block[2] = {kApplicationExit, static_cast<std::uintptr_t>(status)};
  semihosting_call(kSysExitExtended, block);
  for (;;) __asm__ volatile("wfi");  // only without a debugger: stop here
}

void print_target_lines() {
  console_write("target: Cortex-M7 (QEMU mps2-an500), arm-none-eabi-g++ " __VERSION__
                ", newlib-nano, semihosting\n");
  console_write("target: stack high-water mark ");
  console_write_decimal(stack_bytes_used());
  console_write(" of ");
  console_write_decimal(stack_bytes_reserved());
  console_write(" bytes\n");
}

void halt(const char* message) {
  console_write("halt: ");
  console_write(message);
  console_write("\n");
  exit_program(2);
}

}  // namespace mvox::firmware
