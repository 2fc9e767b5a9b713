#pragma once
// The memory a solve may give its radiosity data (docs/robustness.md,
// "Budgets"): what the machine has, and the default share of it.
#include <cstddef>
#include <string>

namespace lhr {

// The stated margin: a solve's peak resident memory stays within its base
// (the same solve stopped after linking) plus this many times the budget.
inline constexpr double kBudgetPeakMargin = 1.2;

// Of the memory this machine has, the share a solve's radiosity data gets by
// default: with the margin, under a third of the machine beside the base.
inline constexpr double kDefaultMemoryBudgetFraction = 0.25;

// The memory this process may use: the machine's physical memory, or less
// where a control group (a container, a CI runner) limits it. 0 when
// neither can be read.
std::size_t machine_memory_bytes();

// kDefaultMemoryBudgetFraction of machine_memory_bytes(); 0 (no limit) when
// that is unknown.
std::size_t default_memory_budget();

// "512 MiB", "5.9 GiB": a size for a message.
std::string format_bytes(std::size_t bytes);

}  // namespace lhr
