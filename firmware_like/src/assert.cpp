#include "mvox/assert.h"

#include <cstdlib>

namespace mvox {
namespace {

void abort_handler(const char*, const char*, int) { std::abort(); }

AssertHandler g_assert_handler = abort_handler;

}  // namespace

AssertHandler set_assert_handler(AssertHandler handler) {
  AssertHandler previous = g_assert_handler;
  g_assert_handler = handler ? handler : abort_handler;
  return previous;
}

void assert_failed(const char* expression, const char* file, int line) {
  g_assert_handler(expression, file, line);
  std::abort();  // a handler must not return into a broken invariant
}

}  // namespace mvox
