#include "pipeline/memory_plan.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>

#include "error.h"

namespace mvox {
namespace {

// A limit file of the control group this process is in (cgroup v2 first, then v1), or nothing
// when there is none or it says "max".
std::optional<std::uint64_t> cgroup_memory_limit() {
  std::ifstream membership("/proc/self/cgroup");
  std::string line;
  std::vector<std::string> candidates;
  while (std::getline(membership, line)) {
    if (line.compare(0, 3, "0::") == 0)  // v2: one unified hierarchy
      candidates.push_back("/sys/fs/cgroup" + line.substr(3) + "/memory.max");
  }
  candidates.push_back("/sys/fs/cgroup/memory.max");
  candidates.push_back("/sys/fs/cgroup/memory/memory.limit_in_bytes");  // v1
  for (const std::string& path : candidates) {
    std::ifstream file(path);
    std::string value;
    if (!(file >> value) || value == "max") continue;
    char* end = nullptr;
    const unsigned long long bytes = std::strtoull(value.c_str(), &end, 10);
    // v1 reports "no limit" as a huge number near 2^63.
    if (end != value.c_str() && *end == '\0' && bytes > 0 && bytes < (1ull << 62)) return bytes;
  }
  return std::nullopt;
}

}  // namespace

std::uint64_t MemoryPlan::job_bytes() const {
  std::uint64_t sum = 0;
  for (const MemoryItem& item : items) sum += item.bytes;
  return sum;
}

MemoryBudget default_memory_budget() {
  MemoryBudget budget;
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_bytes = ::sysconf(_SC_PAGESIZE);
  if (pages > 0 && page_bytes > 0) {
    budget.bytes = static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_bytes);
    budget.source = "this machine's physical memory";
  }
  if (const std::optional<std::uint64_t> limit = cgroup_memory_limit();
      limit && (budget.bytes == 0 || *limit < budget.bytes)) {
    budget.bytes = *limit;
    budget.source = "the memory limit of this process's control group (memory.max)";
  }
  struct rlimit address_space {};
  if (::getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY &&
      (budget.bytes == 0 || address_space.rlim_cur < budget.bytes)) {
    budget.bytes = address_space.rlim_cur;
    budget.source = "the address-space limit (ulimit -v)";
  }
  return budget;
}

std::optional<std::uint64_t> parse_memory_size(const std::string& text) {
  if (text == "none") return std::uint64_t{0};
  if (text.empty() || !(std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '.'))
    return std::nullopt;
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  std::string unit(end);
  if (unit.size() >= 2 &&
      (unit.substr(unit.size() - 2) == "iB" || unit.substr(unit.size() - 2) == "ib"))
    unit.resize(unit.size() - 2);
  else if (unit.size() == 2 && (unit[1] == 'B' || unit[1] == 'b'))
    unit.resize(1);
  double scale = 1;
  if (unit == "B" || unit == "b") unit.clear();
  if (unit.size() == 1) {
    const char* const kUnits = "KMGT";
    const char* found = std::strchr(kUnits, std::toupper(static_cast<unsigned char>(unit[0])));
    if (found == nullptr || *found == '\0') return std::nullopt;
    scale = std::ldexp(1.0, 10 * static_cast<int>(found - kUnits + 1));
  } else if (!unit.empty()) {
    return std::nullopt;
  }
  const double bytes = number * scale;
  if (!std::isfinite(bytes) || bytes < 0 || bytes >= std::ldexp(1.0, 63)) return std::nullopt;
  return static_cast<std::uint64_t>(std::llround(bytes));
}

std::string memory_text(std::uint64_t bytes) {
  static const char* const kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double value = static_cast<double>(bytes);
  int unit = 0;
  while (value >= 1024 && unit < 6) {
    value /= 1024;
    ++unit;
  }
  char text[32];
  if (unit == 0)
    std::snprintf(text, sizeof text, "%llu B", static_cast<unsigned long long>(bytes));
  else
    std::snprintf(text, sizeof text, value < 10 ? "%.1f %s" : "%.0f %s", value, kUnits[unit]);
  return text;
}

void check_memory_budget(const MemoryPlan& plan, const MemoryBudget& budget,
                         const std::string& subject) {
  if (budget.bytes == 0 || plan.total_bytes() <= budget.bytes) return;
  std::vector<MemoryItem> largest = plan.items;
  std::stable_sort(largest.begin(), largest.end(),
                   [](const MemoryItem& a, const MemoryItem& b) { return a.bytes > b.bytes; });
  std::string parts;
  for (std::size_t i = 0; i < largest.size() && i < 3; ++i)
    if (largest[i].bytes > 0)
      parts += (parts.empty() ? "" : ", ") + largest[i].name + " " + memory_text(largest[i].bytes);
  throw Error(subject, "needs " + memory_text(plan.total_bytes()) + " (" + parts + ", ...; " +
                           memory_text(plan.process_bytes) +
                           " of it the program and its libraries), over the " +
                           (budget.source.rfind("--", 0) == 0 ? budget.source + " budget of "
                                                              : "memory budget of ") +
                           memory_text(budget.bytes) +
                           (budget.source.rfind("--", 0) == 0 ? "" : ", " + budget.source) +
                           "; mvox extract --dry-run lists what it needs");
}

std::string memory_plan_text(const MemoryPlan& plan, const MemoryBudget& budget) {
  constexpr const char* kThisRun = "this run";
  constexpr const char* kProcess = "program and libraries, already in use";
  constexpr const char* kTotal = "total";
  // The names in a column as wide as the longest, so that the sizes line up.
  std::size_t width = std::strlen(kProcess);
  for (const MemoryItem& item : plan.items) width = std::max(width, item.name.size());
  std::string text;
  auto add_line = [&](const std::string& name, std::uint64_t bytes) {
    text += "  " + name + std::string(width - name.size(), ' ');
    const std::string size = memory_text(bytes);
    text += std::string(size.size() < 13 ? 13 - size.size() : 1, ' ') + size + "\n";
  };
  for (const MemoryItem& item : plan.items) add_line(item.name, item.bytes);
  add_line(kThisRun, plan.job_bytes());
  add_line(kProcess, plan.process_bytes);
  add_line(kTotal, plan.total_bytes());
  if (budget.bytes == 0) {
    text += "  budget: none\n";
  } else {
    text += "  budget: " + memory_text(budget.bytes) + " (" + budget.source +
            "): " + (plan.total_bytes() <= budget.bytes ? "fits" : "exceeded") + "\n";
  }
  return text;
}

}  // namespace mvox
