#include "read/header_text.h"

#include <cmath>
#include <cstdlib>

namespace mvox {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

bool all_digits(std::string_view text) {
  if (text.empty()) return false;
  for (char c : text)
    if (c < '0' || c > '9') return false;
  return true;
}

}  // namespace

std::vector<HeaderLine> split_header_lines(std::string_view text,
                                           std::vector<std::size_t>* offset_after) {
  std::vector<HeaderLine> lines;
  if (offset_after) offset_after->clear();
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    const std::size_t stop = end == std::string_view::npos ? text.size() : end;
    std::string_view line = text.substr(start, stop - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back({line, lines.size() + 1});
    const std::size_t next = end == std::string_view::npos ? text.size() : end + 1;
    if (offset_after) offset_after->push_back(next);
    start = next;
  }
  return lines;
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && (is_blank(text.front()) || text.front() == '\n')) text.remove_prefix(1);
  while (!text.empty() && (is_blank(text.back()) || text.back() == '\n')) text.remove_suffix(1);
  return text;
}

std::string lowercase(std::string_view text) {
  std::string result(text);
  for (char& c : result)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return result;
}

std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_blank(text[i])) ++i;
    const std::size_t start = i;
    while (i < text.size() && !is_blank(text[i])) ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
  return words;
}

bool parse_unsigned(std::string_view text, std::uint64_t max, std::uint64_t* value) {
  if (!all_digits(text)) return false;
  std::uint64_t result = 0;
  for (char c : text) {
    const auto digit = static_cast<std::uint64_t>(c - '0');
    // Checked before each step so that a long run of digits cannot wrap around.
    if (result > (max - digit) / 10) return false;
    result = result * 10 + digit;
  }
  *value = result;
  return true;
}

bool parse_signed(std::string_view text, std::int64_t max, std::int64_t* value) {
  const bool negative = !text.empty() && text.front() == '-';
  if (negative) text.remove_prefix(1);
  std::uint64_t magnitude = 0;
  if (!parse_unsigned(text, static_cast<std::uint64_t>(max), &magnitude)) return false;
  *value = negative ? -static_cast<std::int64_t>(magnitude) : static_cast<std::int64_t>(magnitude);
  return true;
}

bool parse_real(std::string_view text, bool allow_nan, double* value) {
  if (text.empty() || text.size() > 64) return false;
  const std::string lower = lowercase(text);
  if (lower == "nan" || lower == "+nan" || lower == "-nan") {
    if (!allow_nan) return false;
    *value = std::nan("");
    return true;
  }
  // strtod would also take hexadecimal, "inf" and leading blanks; headers hold plain decimals,
  // so anything but these characters is refused before it gets a say.
  for (char c : lower) {
    const bool allowed = (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e';
    if (!allowed) return false;
  }
  // mvox never calls setlocale, so strtod reads the C locale's '.' decimal point.
  const std::string copy(text);
  char* end = nullptr;
  const double result = std::strtod(copy.c_str(), &end);
  if (end != copy.c_str() + copy.size() || !std::isfinite(result)) return false;
  *value = result;
  return true;
}

std::string quoted(std::string_view text) {
  constexpr std::size_t kMaxShown = 60;
  std::string result = "\"";
  for (std::size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
    const char c = text[i];
    result += (c >= 0x20 && c < 0x7f) ? c : '?';
  }
  if (text.size() > kMaxShown) result += "...";
  return result + "\"";
}

}  // namespace mvox
