#pragma once
// Which optional x86-64 instructions the fast engine's hot loops may use. The build targets the
// x86-64 baseline (SSE2), so the AVX2 loops (engine.cpp) are compiled per function with
// MVOX_TARGET_AVX2 and chosen once per Engine::init by cpu_has_avx2_bmi2().
//
// The CPU is asked through CPUID directly: __builtin_cpu_supports would pull in libgcc's
// __cpu_model and __cpu_indicator_init, which the core may not reference
// (tests/core/core_symbols_test.sh). Other compilers and architectures keep the baseline loops.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MVOX_HAVE_AVX2_PATH 1
#include <cpuid.h>

#include <atomic>
// For a function compiled for AVX2, BMI1/2 and POPCNT. `flatten` inlines everything it calls
// (the walk's template, its action, the running counts' methods): GCC and clang refuse to inline
// a function compiled for AVX2 into one that is not, so without it those would stay calls.
#define MVOX_TARGET_AVX2 __attribute__((target("avx2,bmi,bmi2,popcnt"), flatten))
// For the small AVX2 helpers that a MVOX_TARGET_AVX2 function inlines.
#define MVOX_AVX2_HELPER __attribute__((target("avx2,bmi,bmi2,popcnt")))
#else
#define MVOX_HAVE_AVX2_PATH 0
#endif

namespace mvox {

// True when this CPU and its operating system run AVX2, BMI1, BMI2 and POPCNT instructions, as
// the CPU itself says at every call (cpu_has_avx2_bmi2 below keeps the answer).
inline bool cpu_reports_avx2_bmi2() {
#if MVOX_HAVE_AVX2_PATH
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (!__get_cpuid(1, &eax, &ebx, &ecx, &edx)) return false;
  const bool popcnt = ecx >> 23 & 1, osxsave = ecx >> 27 & 1, avx = ecx >> 28 & 1;
  if (!popcnt || !osxsave || !avx) return false;
  // The OS must save the XMM and YMM registers on a context switch (XCR0 bits 1 and 2).
  unsigned xcr0 = 0, xcr0_high = 0;
  __asm__("xgetbv" : "=a"(xcr0), "=d"(xcr0_high) : "c"(0));
  if ((xcr0 & 6u) != 6u) return false;
  if (!__get_cpuid_count(7, 0, &eax, &ebx, &ecx, &edx)) return false;
  const bool bmi1 = ebx >> 3 & 1, avx2 = ebx >> 5 & 1, bmi2 = ebx >> 8 & 1;
  return bmi1 && avx2 && bmi2;
#else
  return false;
#endif
}

// Kept after the first call: under a hypervisor each cpuid and xgetbv traps to it, about 8
// microseconds here, and Engine::init asks once per slab (64 slabs in a 256x256x1024 run). A
// constant-initialised atomic, not a static initialised by a call, which would need the C++
// runtime's guard functions (the core calls none: core_symbols_test.sh); threads that race to
// the first call each ask the CPU and store the same answer. Once per process.
inline bool cpu_has_avx2_bmi2() {
#if MVOX_HAVE_AVX2_PATH
  static std::atomic<unsigned char> known{0};  // 0: not asked yet, 1: no, 2: yes
  unsigned char answer = known.load(std::memory_order_relaxed);
  if (answer == 0) {
    answer = cpu_reports_avx2_bmi2() ? 2 : 1;
    known.store(answer, std::memory_order_relaxed);
  }
  return answer == 2;
#else
  return false;
#endif
}

}  // namespace mvox
