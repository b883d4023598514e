#include "mpi/mpi_world.h"

#include <cstdio>
#include <cstdlib>

namespace mvox {

MpiWorld::MpiWorld(int* argc, char*** argv) {
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    std::fputs("mvox-mpi: error: MPI: cannot initialize\n", stderr);
    std::exit(1);
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiWorld::~MpiWorld() { MPI_Finalize(); }

int MpiWorld::lowest_failed(bool failed) const {
  const int mine = failed ? rank_ : size_;
  int lowest = size_;
  MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, comm());
  return lowest < size_ ? lowest : -1;
}

void MpiWorld::step(const std::function<void()>& body) {
  std::exception_ptr failure;
  try {
    body();
  } catch (...) {
    failure = std::current_exception();
  }
  joined_ = true;
  const int lowest = lowest_failed(failure != nullptr);
  if (lowest < 0) return;
  if (lowest == rank_) std::rethrow_exception(failure);
  throw OtherRankFailed();
}

bool MpiWorld::fail_before_join() {
  joined_ = true;
  return lowest_failed(true) == rank_;
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
  if (MPI_Error_string(code, text, &length) != MPI_SUCCESS) return "MPI error " + std::to_string(code);
  return std::string(text, static_cast<std::size_t>(length));
}

}  // namespace mvox
