#pragma once
// Counts heap allocations, for tests that prove code allocates nothing. Linking
// counting_allocator.cpp into a test binary replaces the global operator new for that binary
// only (so it is not part of the shared test support library).
#include <cstddef>

namespace mvox::test {

// Counts every operator new while it exists.
class AllocationWindow {
 public:
  AllocationWindow();
  ~AllocationWindow();
  AllocationWindow(const AllocationWindow&) = delete;
  AllocationWindow& operator=(const AllocationWindow&) = delete;
  std::size_t count() const;
};

}  // namespace mvox::test
