#pragma once
// A nameless temporary file for output that has to wait (PLY faces until the vertex count is
// known).
#include <cstddef>
#include <cstdint>
#include <string>

#include "write/buffered_writer.h"

namespace mvox {

class OutputFile;

// Created in `directory` and unlinked at once, so it vanishes however the process ends, even
// when killed. Bytes are appended, then copied in order into an OutputFile. Errors throw
// mvox::Error with `subject` (the real output's name), e.g.
// "out/mesh.ply: write failed on temporary file: No space left on device".
class ScratchFile {
 public:
  ScratchFile(const std::string& directory, const std::string& subject);
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  // Appends `size` bytes. Throws mvox::Error.
  void write(const void* data, std::size_t size) {
    if (const int error = writer_.write(data, size)) fail_write(error);
  }
  // As OutputFile::reserve() and commit(): records formatted in place.
  char* reserve(std::size_t size) {
    int error = 0;
    char* room = writer_.reserve(size, &error);
    if (room == nullptr) fail_write(error);
    return room;
  }
  void commit(std::size_t used) { writer_.commit(used); }

  std::uint64_t bytes_written() const { return writer_.bytes_written(); }

  // Appends everything written so far to `out`. Call once, as the last use of this file.
  void copy_to(OutputFile& out);

  // Reads `size` bytes at `offset` back (flushing what is buffered first), for files that are
  // written, then replayed in another order (mvox extract --labels). Throws mvox::Error.
  void read_at(std::uint64_t offset, void* data, std::size_t size);

 private:
  [[noreturn]] void fail_write(int error);

  std::string subject_;
  BufferedWriter writer_;
};

}  // namespace mvox
