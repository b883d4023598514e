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
// the failure, these end quietly with a failing exit code.
struct OtherRankFailed : std::exception {
  const char* what() const noexcept override { return "another rank failed"; }
};

class MpiWorld {
 public:
  // MPI_Init_thread: mvox's own threads (reading ahead, background writes, the interrupt
  // handler) never call MPI; only the main thread does.
  MpiWorld(int* argc, char*** argv);
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
  void join() { step([] {}); }
  bool joined() const { return joined_; }
  // For a rank that failed before join(): takes part in the others' join() as the failing
  // rank, and tells whether this rank is the one to report (the lowest failing one).
  bool fail_before_join();

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
  // The lowest rank that passes `failed`, or -1.
  int lowest_failed(bool failed) const;

  int rank_ = 0;
  int size_ = 1;
  bool joined_ = false;
};

// MPI's message for an error code, for a one-line error.
std::string mpi_error_text(int code);

}  // namespace mvox
