#include "mpi/mpi_file_stream.h"

#include <cerrno>
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
  write_fully_at(file_, at_, buffer_.get(), used_, subject_);
  at_ += used_;
  used_ = 0;
}

void write_fully_at(MPI_File file, std::uint64_t at, const void* data, std::size_t size,
                    const std::string& subject) {
  MPI_Status status;
  errno = 0;
  const int code = MPI_File_write_at(file, static_cast<MPI_Offset>(at), data,
                                     static_cast<int>(size), MPI_BYTE, &status);
  if (code != MPI_SUCCESS) throw Error(subject, "write failed: " + mpi_error_text(code));
  int written = 0;
  if (MPI_Get_count(&status, MPI_BYTE, &written) == MPI_SUCCESS &&
      written == static_cast<int>(size))
    return;
  // The file system's reason, when the failed call left it in errno.
  const int error = errno;
  throw Error(subject,
              "write failed: " + (error != 0 ? errno_text(error)
                                             : "only " + std::to_string(written) + " of " +
                                                   std::to_string(size) + " bytes written"));
}

}  // namespace mvox
