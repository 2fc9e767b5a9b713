#include "radiosity/shooter_spread.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace lhr {

namespace {

Rgb abs_difference(const Rgb& a, const Rgb& b) {
  return Rgb(std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2]));
}

void raise_to(Rgb& bound, const Rgb& value) {
  for (int k = 0; k < 3; ++k) bound[k] = std::max(bound[k], value[k]);
}

}  // namespace

std::vector<Rgb> linear_node_spread(const SurfaceHierarchy& h, const std::vector<Rgb>& L) {
  const std::size_t n = h.num_nodes();
  std::vector<Rgb> spread(n, Rgb(0, 0, 0));
  // Children have larger ids than their parent: one backward sweep.
  for (std::size_t i = n; i-- > 0;) {
    const NodeId node = static_cast<NodeId>(i);
    if (h.is_leaf(node)) continue;
    const auto& v = h.corners(node);
    // The centre child's corner k is the midpoint of the edge opposite corner k.
    const auto& m = h.corners(h.child(node, 3));
    std::array<Rgb, 3> off;
    for (int k = 0; k < 3; ++k) off[k] = abs_difference(L[m[k]], 0.5 * (L[v[(k + 1) % 3]] + L[v[(k + 2) % 3]]));
    Rgb bound(0, 0, 0);
    for (int c = 0; c < 4; ++c) {
      // Child c < 3 holds corner c and the midpoints of the two edges through
      // it, i.e. all midpoints but m[c]; the centre child holds all three.
      Rgb corners_off(0, 0, 0);
      for (int k = 0; k < 3; ++k) {
        if (k != c) raise_to(corners_off, off[k]);
      }
      raise_to(bound, spread[h.child(node, c)] + corners_off);
    }
    spread[i] = bound;
  }
  return spread;
}

std::vector<Rgb> constant_node_spread(const SurfaceHierarchy& h, const std::vector<Rgb>& L) {
  const std::size_t n = h.num_nodes();
  std::vector<Rgb> lo(L.begin(), L.begin() + static_cast<std::ptrdiff_t>(n));
  std::vector<Rgb> hi = lo;
  std::vector<Rgb> spread(n, Rgb(0, 0, 0));
  for (std::size_t i = n; i-- > 0;) {
    const NodeId node = static_cast<NodeId>(i);
    if (h.is_leaf(node)) continue;
    for (int c = 0; c < 4; ++c) {
      const NodeId child = h.child(node, c);
      for (int k = 0; k < 3; ++k) {
        lo[i][k] = c == 0 ? lo[child][k] : std::min(lo[i][k], lo[child][k]);
        hi[i][k] = c == 0 ? hi[child][k] : std::max(hi[i][k], hi[child][k]);
      }
    }
    for (int k = 0; k < 3; ++k) spread[i][k] = std::max(hi[i][k] - L[i][k], L[i][k] - lo[i][k]);
  }
  return spread;
}

}  // namespace lhr
