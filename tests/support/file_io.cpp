#include "file_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace mvox::test {

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  EXPECT_TRUE(out.good()) << path;
}

void write_bytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  EXPECT_TRUE(out.good()) << path;
}

void touch(const std::filesystem::path& path) { write_bytes(path, std::vector<unsigned char>{}); }

std::vector<unsigned char> committed_fuzz_seed(const std::filesystem::path& corpus_dir,
                                               const std::string& name,
                                               const std::vector<unsigned char>& made) {
  if (const char* write_to = std::getenv("MVOX_WRITE_FUZZ_SEEDS"))
    write_bytes(std::filesystem::path(write_to) / name, made);
  const std::filesystem::path committed = corpus_dir / name;
  if (!std::filesystem::exists(committed)) {
    ADD_FAILURE() << committed << " is missing";
    return {};
  }
  const std::string bytes = read_bytes(committed);
  return std::vector<unsigned char>(bytes.begin(), bytes.end());
}

bool exists(const std::string& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) == 0;
}

std::string ply_body(const std::filesystem::path& path) {
  const std::string bytes = read_bytes(path);
  const std::size_t end = bytes.find("end_header\n");
  return end == std::string::npos ? "" : bytes.substr(end + 11);
}

}  // namespace mvox::test
