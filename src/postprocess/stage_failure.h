#pragma once
// What a stage between the engine and the sinks (smoothing, decimation) keeps when it fails.
// The engine is built without exceptions, so nothing may leave a call it makes: a failure is
// caught, kept, and returned as a Status from then on, and the pipeline rethrows thrown() once
// the engine has stopped.
#include <exception>

#include "mvox/status.h"

namespace mvox {

class StageFailure {
 public:
  Status status() const { return status_; }
  std::exception_ptr thrown() const { return thrown_; }

  // Runs `step` (which returns a Status) unless a failure is already kept; keeps what it
  // returns, or Status::sink_refused and the exception when it throws.
  template <class Step>
  Status run(Step&& step) {
    if (status_ != Status::ok) return status_;
    try {
      status_ = step();
    } catch (...) {
      thrown_ = std::current_exception();
      status_ = Status::sink_refused;
    }
    return status_;
  }

 private:
  Status status_ = Status::ok;
  std::exception_ptr thrown_;
};

}  // namespace mvox
