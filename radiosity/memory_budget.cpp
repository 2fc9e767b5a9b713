#include "radiosity/memory_budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

namespace lhr {
namespace {

// A control group's limit: cgroup v2's memory.max ("max" when unlimited),
// else cgroup v1's memory.limit_in_bytes (a huge number when unlimited).
std::size_t cgroup_limit_bytes() {
  for (const char* path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(path);
    std::string text;
    if (!(in >> text) || text == "max") continue;
    try {
      const unsigned long long value = std::stoull(text);
      if (value > 0) return static_cast<std::size_t>(value);
    } catch (const std::exception&) {
    }
  }
  return std::numeric_limits<std::size_t>::max();
}

}  // namespace

std::size_t machine_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGE_SIZE);
  const std::size_t physical = pages > 0 && page_size > 0
                                   ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page_size)
                                   : std::numeric_limits<std::size_t>::max();
  const std::size_t bytes = std::min(physical, cgroup_limit_bytes());
  return bytes == std::numeric_limits<std::size_t>::max() ? 0 : bytes;
}

std::size_t default_memory_budget() {
  return static_cast<std::size_t>(kDefaultMemoryBudgetFraction * static_cast<double>(machine_memory_bytes()));
}

std::string format_bytes(std::size_t bytes) {
  constexpr double kMiB = 1024.0 * 1024.0;
  const double mib = static_cast<double>(bytes) / kMiB;
  char text[32];
  if (mib >= 1024.0) {
    std::snprintf(text, sizeof text, "%.1f GiB", mib / 1024.0);
  } else {
    std::snprintf(text, sizeof text, "%.0f MiB", mib);
  }
  return text;
}

}  // namespace lhr
