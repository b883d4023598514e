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

namespace {
const char* program_name = "mvox";
}  // namespace

void set_message_program(const char* name) { program_name = name; }
const char* message_program() { return program_name; }

void print_message(const char* kind, std::string_view text) {
  const std::string line =
      std::string(program_name) + ": " + std::string(kind) + ": " + one_line(text) + "\n";
  std::fputs(line.c_str(), stderr);
}

}  // namespace mvox
