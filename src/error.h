#pragma once
// The host's one exception type: a problem the user can act on, naming what it is about.
#include <stdexcept>
#include <string>

namespace mvox {

// what() reads "SUBJECT: PROBLEM", e.g. "scans/slice_007.png: image is 512x512, expected 256x256".
// SUBJECT is a file name, an option or a command; PROBLEM is one line without a final period.
class Error : public std::runtime_error {
 public:
  Error(const std::string& subject, const std::string& problem)
      : std::runtime_error(subject + ": " + problem), subject_(subject), problem_(problem) {}
  const std::string& subject() const { return subject_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string subject_;
  std::string problem_;
};

// A problem with how mvox was asked to run rather than with a file's contents, found before
// any work: main() exits with 2 for it, as for a malformed option, instead of 1.
class UsageError : public Error {
 public:
  using Error::Error;
};

// "strerror(errno)" as a string, for problems reported by the C library.
std::string errno_text(int error_number);

}  // namespace mvox
