#include "mpi/mpi_world.h"

#include <cstdio>
#include <cstdlib>

namespace mvox {

MpiWorld::MpiWorld(int* argc, char*** argv, ExitCodeOf exit_code_of) : exit_code_of_(exit_code_of) {
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS ||
      provided < MPI_THREAD_FUNNELED) {
    std::fputs("mvox-mpi: error: MPI: cannot start with threads beside the main one\n", stderr);
    std::exit(1);
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiWorld::~MpiWorld() { MPI_Finalize(); }

int MpiWorld::agree(const std::exception_ptr& failure, int* code) const {
  const int mine = failure ? rank_ : size_;
  int lowest = size_;
  MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, comm());
  if (lowest == size_) return -1;
  *code = lowest == rank_ ? exit_code_of_(failure) : 1;
  MPI_Bcast(code, 1, MPI_INT, lowest, comm());
  return lowest;
}

void MpiWorld::step(const std::function<void()>& body) {
  std::exception_ptr failure;
  try {
    body();
  } catch (...) {
    failure = std::current_exception();
  }
  joined_ = true;
  int code = 1;
  const int lowest = agree(failure, &code);
  if (lowest < 0) return;
  if (lowest == rank_) std::rethrow_exception(failure);
  throw OtherRankFailed(code);
}

bool MpiWorld::fail_before_join(const std::exception_ptr& failure, int* code) {
  joined_ = true;
  return agree(failure, code) == rank_;
}

std::string MpiWorld::broadcast(const std::string& text) const {
  unsigned long long length = text.size();
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, comm());
  std::string received = rank_ == 0 ? text : std::string(length, '\0');
  MPI_Bcast(received.data(), static_cast<int>(length), MPI_CHAR, 0, comm());
  return received;
}

std::uint64_t MpiWorld::max(std::uint64_t value) const {
  unsigned long long mine = value, largest = 0;
  MPI_Allreduce(&mine, &largest, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm());
  return largest;
}

std::string mpi_error_text(int code) {
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  if (MPI_Error_string(code, text, &length) != MPI_SUCCESS)
    return "MPI error " + std::to_string(code);
  return std::string(text, static_cast<std::size_t>(length));
}

}  // namespace mvox
