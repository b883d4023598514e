#pragma once
// Test support: whole files in and out, as bytes.
#include <filesystem>
#include <string>

namespace mvox::test {

// The bytes of the file at `path` ("" when it cannot be read).
std::string read_bytes(const std::filesystem::path& path);

// Creates or replaces the file at `path` with `bytes`; a failure fails the test.
void write_bytes(const std::filesystem::path& path, const std::string& bytes);

}  // namespace mvox::test
