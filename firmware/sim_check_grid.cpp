// sim::check_grid without exceptions: the one function of sim/phantom.cpp that the demo's
// phantom (sim/shepp_logan.cpp) calls. The demo builds shepp_logan.cpp as it is but not
// phantom.cpp, which throws std::invalid_argument with a std::string message (and whose
// sample_volume returns a std::vector): the board has no exceptions and no heap. Here an empty
// grid, a programming error in the demo, halts with a message instead.
#include "phantom.h"
#include "platform.h"

namespace mvox::sim {

void check_grid(const Grid& grid, const char* phantom_name) {
  if (grid.width == 0 || grid.height == 0 || grid.depth == 0) {
    firmware::console_write(phantom_name);
    firmware::console_write(": ");
    firmware::halt("the phantom's grid has an empty dimension");
  }
}

}  // namespace mvox::sim
