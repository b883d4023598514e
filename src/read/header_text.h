#pragma once
// Small, strict pieces shared by the text-header parsers (NRRD, MetaImage): lines, words and
// numbers, each either parsed completely or refused. Pure functions, no I/O, so the parsers
// built on them can be fuzzed.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mvox {

// One line of a header: its text without the line end ("\n" or "\r\n") and its 1-based number.
struct HeaderLine {
  std::string_view text;
  std::size_t number = 0;
};

// Cuts `text` into lines at '\n' (a '\r' before it is dropped). The part after the last '\n'
// is a line too when it is not empty. `offset_after` receives, for each line, the offset just
// past its '\n' (text.size() for an unterminated last line), so a parser that stops at a line
// knows where the bytes after the header start.
std::vector<HeaderLine> split_header_lines(std::string_view text,
                                           std::vector<std::size_t>* offset_after);

std::string_view trim(std::string_view text);  // without leading and trailing blanks
std::string lowercase(std::string_view text);  // ASCII only

// The blank-separated words of `text`.
std::vector<std::string_view> split_words(std::string_view text);

// `text` as a whole number, decimal digits only, at most `max`; false if anything else.
bool parse_unsigned(std::string_view text, std::uint64_t max, std::uint64_t* value);
// Like parse_unsigned, with an optional leading '-' (value in [-max, max]).
bool parse_signed(std::string_view text, std::int64_t max, std::int64_t* value);
// `text` as a decimal or exponent floating-point number ("1", "-2.5e-3"), always read in the
// C locale's format; "nan" (any case) gives NaN only when `allow_nan`. Infinity is refused.
bool parse_real(std::string_view text, bool allow_nan, double* value);

// "text" quoted for a message, cut to 60 characters so a binary or endless line stays short,
// with bytes that are not printable ASCII shown as '?'.
std::string quoted(std::string_view text);

}  // namespace mvox
