#pragma once
// For fuzz targets: a property that must hold for every input. A failure prints what broke and
// aborts, which libFuzzer reports as a crash and saves the input that caused it.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#define MVOX_FUZZ_CHECK(condition, what)                                                       \
  do {                                                                                         \
    if (!(condition)) {                                                                        \
      std::fprintf(stderr, "%s:%d: property failed: %s: %s\n", __FILE__, __LINE__, #condition, \
                   std::string(what).c_str());                                                 \
      std::abort();                                                                            \
    }                                                                                          \
  } while (0)

namespace mvox::fuzz {

// mvox's errors are one line of printable text, whatever the input held (README: "When things
// go wrong").
inline bool is_one_printable_line(const char* text) {
  for (const char* c = text; *c != '\0'; ++c)
    if (static_cast<unsigned char>(*c) < 0x20 || *c == 0x7f) return false;
  return std::strlen(text) > 0;
}

}  // namespace mvox::fuzz
