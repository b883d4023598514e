#pragma once
// One section of a file that the ranks of mvox-mpi write together, appended to from a given
// offset on: where a rank writes its records of a mesh in place (placed_part_writer.h). Bytes
// are gathered in a buffer of BufferedWriter::kBufferBytes and written with MPI_File_write_at
// when it is full and when flushed, so that MPI-IO sees few, large writes.
#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace mvox {

// Writes `size` bytes (at most INT_MAX) at `at` of `file` with MPI_File_write_at, and throws
// mvox::Error naming `subject` unless all of them were written. Open MPI reports a write the
// file system refused (a full disk, `ulimit -f`) as a success that wrote fewer bytes, so the
// count is checked, not only the return code.
void write_fully_at(MPI_File file, std::uint64_t at, const void* data, std::size_t size,
                    const std::string& subject);

class MpiFileStream {
 public:
  // `file` stays open while this writes; `subject` names the file in errors.
  MpiFileStream(MPI_File file, std::uint64_t offset, std::string subject);
  MpiFileStream(const MpiFileStream&) = delete;
  MpiFileStream& operator=(const MpiFileStream&) = delete;

  // Room for `size` bytes (at most BufferedWriter::kBufferBytes); commit(used) appends the
  // `used` bytes written there. Throws mvox::Error when a write of the buffer fails.
  char* reserve(std::size_t size);
  void commit(std::size_t used) {
    used_ += used;
    total_ += used;
  }
  // Writes the buffered bytes. Throws mvox::Error.
  void flush();
  // Bytes appended so far, written or buffered.
  std::uint64_t bytes_written() const { return total_; }

 private:
  MPI_File file_;
  std::uint64_t at_;  // where the buffer's first byte goes
  std::string subject_;
  std::unique_ptr<char[]> buffer_;
  std::size_t used_ = 0;
  std::uint64_t total_ = 0;
};

}  // namespace mvox
