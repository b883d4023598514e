#pragma once
// Validators for the command line's numbers, stricter than CLI11's own: CLI::Range lets NaN
// through (every comparison with NaN is false), CLI::PositiveNumber prints its bound with 300
// digits, and CLI11 reads integers with strtoull, which wraps "-1" and "4294967297" around and
// reads "010" as octal. A refusal is a usage error (exit 2) naming the option:
// "--view: must be a number from -360 to 360, got nan".
#include <CLI/CLI.hpp>
#include <cstdint>

namespace mvox {

// A finite number (refuses nan and inf), for thresholds.
CLI::Validator finite_number();

// A finite number from `lowest` to `highest`, for angles.
CLI::Validator number_from(double lowest, double highest);

// A voxel spacing: positive, finite, and in the range float coordinates allow
// (spacing_problem() in world_transform.h).
CLI::Validator spacing_number();

// A coordinate of the origin: finite and within float's range (origin_problem()).
CLI::Validator origin_number();

// A whole number from `lowest` to `highest`, decimal digits only (no sign, no exponent, no
// hexadecimal). A transform, not only a check: it rewrites the text without leading zeros, so
// that CLI11's own conversion cannot read "010" as octal.
CLI::Validator whole_number_from(std::uint64_t lowest, std::uint64_t highest);

// An input argument: "-" stands for standard input (/dev/stdin), as pipelines write it, unless
// a file named "-" exists. Refused when standard input is a terminal: reading it would wait for
// typing that never makes a volume.
CLI::Validator standard_input_dash();

// `text` as a whole number of decimal digits only, at most `highest`; false for anything else,
// an empty text or a value past `highest` included (no wrap-around).
bool parse_whole_number(const std::string& text, std::uint64_t highest, std::uint64_t* value);

}  // namespace mvox
