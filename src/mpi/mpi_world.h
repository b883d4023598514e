#pragma once
// The processes of an mvox-mpi run (MPI_COMM_WORLD) and the few collective steps the
// distributed job needs, with failures agreed on: every rank calls the same steps in the same
// order, so a rank that fails never leaves the others waiting in a collective call.
#include <mpi.h>

#include <cstdint>
#include <exception>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace mvox {

// Thrown on the ranks that did not fail themselves when another rank did: that rank reports
// the failure, these end quietly with the same exit code.
struct OtherRankFailed : std::exception {
  explicit OtherRankFailed(int code) : exit_code(code) {}
  const char* what() const noexcept override { return "another rank failed"; }
  int exit_code;
};

class MpiWorld {
 public:
  // MPI_Init_thread: mvox's own threads (reading ahead, background writes, the interrupt
  // handler) never call MPI; only the main thread does. `exit_code_of` gives the exit code a
  // failure ends the process with; every rank ends with the reporting rank's.
  using ExitCodeOf = int (*)(const std::exception_ptr& failure);
  MpiWorld(int* argc, char*** argv, ExitCodeOf exit_code_of);
  ~MpiWorld();
  MpiWorld(const MpiWorld&) = delete;
  MpiWorld& operator=(const MpiWorld&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  MPI_Comm comm() const { return MPI_COMM_WORLD; }

  // One step of the run on every rank: runs `body`, then agrees with the others on whether any
  // rank failed. When some did, the lowest failing rank rethrows its own failure (the ranks
  // take slices in order, so that is the failure one process reading the volume in order would
  // report) and every other rank throws OtherRankFailed.
  void step(const std::function<void()>& body);
  // The first step, which a rank takes when it has read its options and opened its input
  // without error.
  void join() {
    step([] {});
  }
  bool joined() const { return joined_; }
  // For a rank that failed before join(): takes part in the others' join() as the failing
  // rank, and tells whether this rank is the one to report (the lowest failing one); `*code`
  // is the exit code every rank ends with.
  bool fail_before_join(const std::exception_ptr& failure, int* code);

  // Every rank's `mine`, in rank order (T trivially copyable).
  template <class T>
  std::vector<T> all_gather(const T& mine) const {
    static_assert(std::is_trivially_copyable<T>::value, "sent as bytes");
    std::vector<T> all(static_cast<std::size_t>(size_));
    MPI_Allgather(&mine, sizeof(T), MPI_BYTE, all.data(), sizeof(T), MPI_BYTE, comm());
    return all;
  }
  // Rank 0's `text` on every rank.
  std::string broadcast(const std::string& text) const;
  // The largest of every rank's `value`.
  std::uint64_t max(std::uint64_t value) const;

 private:
  // Every rank's `failure` (null: none) agreed on: the lowest rank that failed, or -1, and that
  // rank's exit code in `*code`.
  int agree(const std::exception_ptr& failure, int* code) const;

  ExitCodeOf exit_code_of_;
  int rank_ = 0;
  int size_ = 1;
  bool joined_ = false;
};

// MPI's message for an error code, for a one-line error.
std::string mpi_error_text(int code);

}  // namespace mvox
