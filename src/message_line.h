#pragma once
// Every line mvox prints (errors, warnings, notes, summaries) stays one line, whatever the file
// names and option values in it hold: a path with a newline must not split an error in two,
// and an escape sequence in a name must not reach the terminal.
#include <string>
#include <string_view>

namespace mvox {

// `text` with its control characters made visible: '\n' becomes the two characters \n, every
// other byte below 0x20 and 0x7f becomes \xNN (\r as \x0d, ESC as \x1b). Other bytes pass as
// they are, UTF-8 included. A backslash is left alone, so ordinary text reads as before.
std::string one_line(std::string_view text);

// Prints "mvox: KIND: TEXT" and a newline on standard error, TEXT through one_line(). KIND is
// "error", "warning" or "note".
void print_message(const char* kind, std::string_view text);
// The name that starts those lines: "mvox" unless another executable (mvox-mpi) says so, once,
// before any thread starts. `name` must outlive every message.
void set_message_program(const char* name);
const char* message_program();

}  // namespace mvox
