#pragma once
// A one-line progress report on standard error for long runs: slices done, rate, time left.
// Shown only when standard error is a terminal and the user did not ask for quiet.
#include <chrono>
#include <cstdint>
#include <string>

namespace mvox {

class ProgressLine {
 public:
  // `total_slices` may be 0 when unknown; `enabled` false makes every call a no-op.
  ProgressLine(std::string label, std::uint32_t total_slices, bool enabled);
  ~ProgressLine();  // ends the line if anything was drawn

  void update(std::uint32_t slices_done);
  void finish();
  bool enabled() const { return enabled_; }

  // True when standard error is a terminal (where a redrawn line makes sense).
  static bool stderr_is_terminal();

 private:
  std::string label_;
  std::uint32_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  // The clock is read every `stride_` slices (1 to 1024), adapted to keep about a millisecond
  // between readings: a reading per slice costs more than a slice of a few voxels takes to
  // extract.
  std::chrono::steady_clock::time_point last_look_;
  std::uint32_t looked_at_ = 0;  // slices_done when the clock was last read
  std::uint32_t stride_ = 1;
};

}  // namespace mvox
