#include "message_line.h"

#include <cstdio>

namespace mvox {

std::string one_line(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte == '\n') {
      out += "\\n";
    } else if (byte < 0x20 || byte == 0x7f) {
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out;
}

void print_message(const char* kind, std::string_view text) {
  const std::string line = "mvox: " + std::string(kind) + ": " + one_line(text) + "\n";
  std::fputs(line.c_str(), stderr);
}

}  // namespace mvox
