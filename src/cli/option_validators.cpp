#include "cli/option_validators.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "write/mesh/world_transform.h"

namespace mvox {
namespace {

// `text` read whole as a number (strtod's syntax, so "nan" and "inf" too); false when anything
// is left over or nothing was read.
bool parse_number(const std::string& text, double* value) {
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0';
}

std::string bound_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

}  // namespace

bool parse_whole_number(const std::string& text, std::uint64_t highest, std::uint64_t* value) {
  if (text.empty()) return false;
  std::uint64_t result = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return false;
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (result > (highest - digit) / 10) return false;  // result * 10 + digit > highest
    result = result * 10 + digit;
  }
  *value = result;
  return true;
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        if (!parse_number(text, &value)) return "'" + text + "' is not a number";
        if (!std::isfinite(value)) return "'" + text + "' is not a finite number";
        return {};
      },
      "NUMBER");
}

CLI::Validator number_from(double lowest, double highest) {
  return CLI::Validator(
      [lowest, highest](std::string& text) -> std::string {
        double value = 0;
        // Written so that NaN fails: it is neither >= lowest nor <= highest.
        if (parse_number(text, &value) && value >= lowest && value <= highest) return {};
        return "must be a number from " + bound_text(lowest) + " to " + bound_text(highest) +
               ", got " + text;
      },
      "NUMBER in [" + bound_text(lowest) + ", " + bound_text(highest) + "]");
}

CLI::Validator spacing_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        if (!parse_number(text, &value)) return "must be positive and finite, got " + text;
        return spacing_problem(value, text);
      },
      "POSITIVE");
}

CLI::Validator origin_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        if (!parse_number(text, &value)) return "'" + text + "' is not a number";
        return origin_problem(value, text);
      },
      "NUMBER");
}

CLI::Validator whole_number_from(std::uint64_t lowest, std::uint64_t highest) {
  return CLI::Validator(
      [lowest, highest](std::string& text) -> std::string {
        std::uint64_t value = 0;
        if (!parse_whole_number(text, highest, &value) || value < lowest)
          return "must be a whole number from " + std::to_string(lowest) + " to " +
                 std::to_string(highest) + ", got " + text;
        text = std::to_string(value);
        return {};
      },
      "INT in [" + std::to_string(lowest) + " - " + std::to_string(highest) + "]");
}

CLI::Validator standard_input_dash() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::error_code error;
        if (text != "-" || std::filesystem::exists(std::filesystem::symlink_status(text, error)))
          return {};
        if (::isatty(STDIN_FILENO))
          return "- is standard input, which is a terminal here: pipe the volume in (zcat "
                 "scan.raw.gz | mvox extract - --raw WxHxD:TYPE ...) or name its file";
        text = "/dev/stdin";
        return {};
      },
      "");
}

}  // namespace mvox
