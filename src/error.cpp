#include "error.h"

#include <cstring>

namespace mvox {

std::string errno_text(int error_number) { return std::strerror(error_number); }

}  // namespace mvox
