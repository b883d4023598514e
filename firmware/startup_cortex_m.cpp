// Reset and fault handling for a Cortex-M7 (ARMv7E-M with a double-precision FPU), with the
// memory layout of mps2_an500.ld. What a C runtime's crt0 would do, kept short and visible:
//   1. let the FPU be used (the build uses hardware floating point);
//   2. copy .data from flash to RAM and clear .bss;
//   3. paint the unused stack, so that its high-water mark can be measured at the end;
//   4. run static constructors, call main(), exit with its status (semihosting).
#include <cstddef>
#include <cstdint>

#include "platform.h"

extern "C" {
// Defined by the linker script.
extern std::uint32_t __data_start[], __data_end[], __data_load[];
extern std::uint32_t __bss_start[], __bss_end[];
extern std::uint32_t __stack_bottom[], __stack_top[];
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
int main();
void reset_handler();
}

namespace mvox::firmware {
namespace {

constexpr std::uint32_t kStackPaint = 0x5a5aa5a5u;

// Everything after the FPU is switched on. noinline, so that no floating-point instruction of
// it can be scheduled before the switch.
[[noreturn]] __attribute__((noinline)) void start() {
  for (std::uint32_t *from = __data_load, *to = __data_start; to < __data_end;) *to++ = *from++;
  for (std::uint32_t* p = __bss_start; p < __bss_end; ++p) *p = 0;
  // Paint from the stack's bottom up to 64 bytes below the stack pointer: nothing lives there.
  std::uint32_t* sp;
  __asm__ volatile("mov %0, sp" : "=r"(sp));
  for (volatile std::uint32_t* p = __stack_bottom; p < sp - 16; ++p) *p = kStackPaint;
  for (auto** constructor = __init_array_start; constructor < __init_array_end; ++constructor)
    (**constructor)();
  exit_program(main());
}

[[noreturn]] void fault(const char* name) { halt(name); }

void nmi_handler() { fault("NMI"); }
void hard_fault_handler() { fault("HardFault (CPU fault)"); }
void mem_manage_handler() { fault("MemManage fault"); }
void bus_fault_handler() { fault("BusFault"); }
void usage_fault_handler() { fault("UsageFault"); }
void unexpected_handler() { fault("unexpected exception or interrupt"); }

using Handler = void (*)();

}  // namespace

// Bytes of stack below its top that were ever written since reset (the paint is gone).
std::size_t stack_bytes_used() {
  const std::uint32_t* p = __stack_bottom;
  while (p < __stack_top && *p == kStackPaint) ++p;
  return static_cast<std::size_t>(__stack_top - p) * sizeof(std::uint32_t);
}

std::size_t stack_bytes_reserved() {
  return static_cast<std::size_t>(__stack_top - __stack_bottom) * sizeof(std::uint32_t);
}

// The vector table, placed at address 0 by the linker script: the initial stack pointer, then
// the 15 system exceptions. No external interrupt is enabled, so none has an entry.
struct VectorTable {
  void* initial_stack_pointer;
  Handler handlers[15];
};

extern "C" __attribute__((section(".vectors"), used))
const VectorTable vector_table = {__stack_top,  //  0 initial stack pointer
                                  {
                                      reset_handler,        //  1 reset
                                      nmi_handler,          //  2 NMI
                                      hard_fault_handler,   //  3 HardFault
                                      mem_manage_handler,   //  4 MemManage
                                      bus_fault_handler,    //  5 BusFault
                                      usage_fault_handler,  //  6 UsageFault
                                      nullptr,              //  7 reserved
                                      nullptr,              //  8 reserved
                                      nullptr,              //  9 reserved
                                      nullptr,              // 10 reserved
                                      unexpected_handler,   // 11 SVCall
                                      unexpected_handler,   // 12 debug monitor
                                      nullptr,              // 13 reserved
                                      unexpected_handler,   // 14 PendSV
                                      unexpected_handler,   // 15 SysTick
                                  }};

}  // namespace mvox::firmware

extern "C" void reset_handler() {
  // CPACR (0xE000ED88): full access to coprocessors 10 and 11, the FPU.
  *reinterpret_cast<volatile std::uint32_t*>(0xE000ED88u) |= 0xfu << 20;
  __asm__ volatile("dsb\n\tisb" ::: "memory");
  mvox::firmware::start();
}
