#include "error_capture.h"

#include <exception>

#include "error.h"

namespace mvox::test {

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.what();
  } catch (const std::exception& other) {
    ADD_FAILURE() << "expected mvox::Error, got: " << other.what();
    return "";
  }
  ADD_FAILURE() << "expected mvox::Error, nothing was thrown";
  return "";
}

}  // namespace mvox::test
