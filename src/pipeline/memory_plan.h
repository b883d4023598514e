#pragma once
// What a run will allocate, known from the input's header before any slice is read, and the
// budget it must fit: `mvox extract --dry-run` prints the plan, --stats reports it beside the
// measured peak, and --max-memory refuses a run whose plan exceeds it before anything is
// allocated.
//
// Every part of a run takes memory that is a function of the slice and picture sizes, never of
// the number of slices, so the plan is exact up to the allocators' rounding and what the
// decoders keep of their own (a few tens of KiB, plus OpenCV's or GDCM's buffers for one image,
// which the reader's line counts).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mvox {

struct MemoryItem {
  std::string name;  // what takes it, for the plan's lines: "engine workspace"
  std::uint64_t bytes = 0;
};

struct MemoryPlan {
  std::vector<MemoryItem> items;  // the run's own allocations
  // Resident before the run: the program and the libraries it has loaded (OpenCV's codecs and
  // their dependencies are most of it).
  std::uint64_t process_bytes = 0;
  // With slab workers: the chunks of recorded output each may hold (SlabOptions::most_chunks),
  // as many as the budget leaves room for; 0 without them.
  unsigned slab_chunks = 0;

  void add(const std::string& name, std::uint64_t bytes) { items.push_back({name, bytes}); }
  std::uint64_t job_bytes() const;                                           // sum of the items
  std::uint64_t total_bytes() const { return process_bytes + job_bytes(); }  // what the budget sees
};

// The most memory a run may take, and where that figure comes from.
struct MemoryBudget {
  std::uint64_t bytes = 0;  // 0: no limit
  std::string source;       // "--max-memory 64M", "physical memory", "the cgroup's memory.max"
};

// The default budget: what this process can get at all, the smallest of the machine's physical
// memory (MemTotal), the memory limit of its control group (memory.max, as containers set)
// and its address-space limit (ulimit -v). A plan above it can only end in swapping or in the
// kernel's out-of-memory killer, which ends mvox without a word; so it is refused up front,
// and below it mvox does not second-guess what other processes leave free.
MemoryBudget default_memory_budget();

// "64M", "2G", "1.5G", "512K", "100000" (bytes), binary units (K = 1024), with an optional
// "iB"/"B" ("64MiB", "64MB" are 64 * 2^20 too); "none" or "0" for no limit (bytes 0). Nothing for
// anything else, or a size beyond 2^63.
std::optional<std::uint64_t> parse_memory_size(const std::string& text);

// "1.3 MiB", "218 KiB", "512 B", "4.0 GiB": sizes as people read them.
std::string memory_text(std::uint64_t bytes);

// Throws mvox::Error naming `subject` (the input) when the plan's total exceeds the budget:
// "needs 4.2 GiB (slice buffers 4.0 GiB, engine workspace ...), over the --max-memory budget of
// 64 MiB". Does nothing without a limit.
void check_memory_budget(const MemoryPlan& plan, const MemoryBudget& budget,
                         const std::string& subject);

// The plan as lines for people, ending in the total and the budget: what --dry-run prints.
std::string memory_plan_text(const MemoryPlan& plan, const MemoryBudget& budget);

}  // namespace mvox
