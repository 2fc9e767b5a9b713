#include "radiosity/receiver_oracle.hpp"

#include <algorithm>
#include <cmath>

namespace lhr {

double ReceiverOracle::display_error(const EdgeValues& edge) const {
  double b_min = edge.total[0] - edge.own[0];
  for (int i = 1; i < 4; ++i) b_min = std::min(b_min, edge.total[i] - edge.own[i]);
  b_min = std::max(0.0, b_min);
  const auto shown = [&](double value) { return tone_.display(b_min + value); };
  const auto& b = edge.own;
  if (std::abs(edge.visibility_1 - edge.visibility_2) < vis_threshold_) {
    return 0.5 * std::abs(shown(b[0]) + shown(b[1]) - shown(b[2]) - shown(b[3]));
  }
  const auto [lo, hi] = std::minmax_element(b.begin(), b.end());
  return shown(*hi) - shown(*lo);
}

}  // namespace lhr
