#include "failed_allocation.h"

#include <atomic>

namespace mvox {
namespace {

std::atomic<std::size_t> g_failed_bytes{0};

}  // namespace

void note_failed_allocation(std::size_t bytes) { g_failed_bytes = bytes; }

std::size_t failed_allocation_bytes() { return g_failed_bytes; }

}  // namespace mvox
