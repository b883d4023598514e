#include "mpi/mpi_file_stream.h"

#include <utility>

#include "error.h"
#include "mpi/mpi_world.h"
#include "write/buffered_writer.h"

namespace mvox {

MpiFileStream::MpiFileStream(MPI_File file, std::uint64_t offset, std::string subject)
    : file_(file),
      at_(offset),
      subject_(std::move(subject)),
      buffer_(new char[BufferedWriter::kBufferBytes]) {}

char* MpiFileStream::reserve(std::size_t size) {
  if (size > BufferedWriter::kBufferBytes)
    throw Error(subject_, "internal error: a run of records larger than the write buffer");
  if (BufferedWriter::kBufferBytes - used_ < size) flush();
  return buffer_.get() + used_;
}

void MpiFileStream::flush() {
  if (used_ == 0) return;
  MPI_Status status;
  const int code = MPI_File_write_at(file_, static_cast<MPI_Offset>(at_), buffer_.get(),
                                     static_cast<int>(used_), MPI_BYTE, &status);
  if (code != MPI_SUCCESS) throw Error(subject_, "write failed: " + mpi_error_text(code));
  int written = 0;
  MPI_Get_count(&status, MPI_BYTE, &written);
  if (written != static_cast<int>(used_))
    throw Error(subject_, "write failed: " + std::to_string(written) + " of " +
                              std::to_string(used_) + " bytes written");
  at_ += used_;
  used_ = 0;
}

}  // namespace mvox
