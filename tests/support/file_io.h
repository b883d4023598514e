#pragma once
// Test support: whole files in and out, as bytes.
#include <filesystem>
#include <string>
#include <vector>

namespace mvox::test {

// The bytes of the file at `path` ("" when it cannot be read).
std::string read_bytes(const std::filesystem::path& path);

// Creates or replaces the file at `path` with `bytes`; a failure fails the test.
void write_bytes(const std::filesystem::path& path, const std::string& bytes);

// The same for bytes held as unsigned char, creating the directories above `path` first.
void write_bytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes);

// An empty file at `path`, creating the directories above it first.
void touch(const std::filesystem::path& path);

// The bytes after a PLY file's header: the mesh itself, without the comment lines that name
// the input, so that meshes from different inputs compare ("" without a header).
std::string ply_body(const std::filesystem::path& path);

// The committed fuzz seed `corpus_dir`/`name` as bytes, after writing `made` there instead of
// into the corpus when MVOX_WRITE_FUZZ_SEEDS=DIR is set (DIR/`name`): tests make their seeds,
// then check that what is committed still behaves as made. A missing seed fails the test and
// gives no bytes.
std::vector<unsigned char> committed_fuzz_seed(const std::filesystem::path& corpus_dir,
                                               const std::string& name,
                                               const std::vector<unsigned char>& made);

// True when `path` names something (stat() succeeds: a dangling link does not count).
bool exists(const std::string& path);

}  // namespace mvox::test
