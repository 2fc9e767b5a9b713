#pragma once
// Long parallel loops that a signal can stop (docs/robustness.md,
// "Interrupted runs"): the work goes in blocks, and the checkpoint runs on
// the calling thread between them, so an interrupt waits for one block, not
// for the whole loop. The checkpoint may throw; the loop then stops there.
#include <algorithm>
#include <cstddef>
#include <functional>

#include <tbb/parallel_for.h>

namespace lhr {

// Enough items per block to keep every core busy (a link's coefficients
// take tens of microseconds), few enough that a block ends within a fraction
// of a second.
inline constexpr std::size_t kInterruptibleBlock = 4096;

template <class Body>
void interruptible_parallel_for(std::size_t n, const std::function<void()>& checkpoint, const Body& body) {
  for (std::size_t begin = 0; begin < n; begin += kInterruptibleBlock) {
    if (checkpoint) checkpoint();
    const std::size_t end = std::min(n, begin + kInterruptibleBlock);
    tbb::parallel_for(begin, end, [&](std::size_t i) { body(i); });
  }
}

}  // namespace lhr
