#pragma once
// Programmer errors (broken invariants) go through MVOX_ASSERT; operating errors are Status values.
// The default handler prints nothing (the core has no stdio) and calls std::abort(); a host or
// a test may install its own.

namespace mvox {

using AssertHandler = void (*)(const char* expression, const char* file, int line);

// Replaces the handler and returns the previous one. Not thread-safe: call at start-up.
AssertHandler set_assert_handler(AssertHandler handler);

[[noreturn]] void assert_failed(const char* expression, const char* file, int line);

}  // namespace mvox

#define MVOX_ASSERT(condition) \
  ((condition) ? static_cast<void>(0) : ::mvox::assert_failed(#condition, __FILE__, __LINE__))

// For invariants checked in hot loops: active in debug builds, compiled out under NDEBUG.
#ifdef NDEBUG
#define MVOX_DEBUG_ASSERT(condition) static_cast<void>(0)
#else
#define MVOX_DEBUG_ASSERT(condition) MVOX_ASSERT(condition)
#endif
