#include "radiosity/shooter_spread.hpp"

#include <algorithm>
#include <array>
#include <cassert>
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

void project_linear_nodes(const SurfaceHierarchy& h, const std::vector<Rgb>& L, const std::vector<double>& node_area,
                          LinearShooterValues& out) {
  const std::size_t n = h.num_nodes();
  out.corners.resize(n);
  out.spread.assign(n, Rgb(0, 0, 0));
  // g[node][l] = ∫ L N_l dA over the node, N_l its hat function at corner l;
  // the hat functions sum to 1, so Σ_l g[node][l] = ∫ L dA.
  std::vector<std::array<Rgb, 3>> g(n);
  // A parent's hat function at each corner of each child, as weights on the
  // parent's corners: 1 at its own corner, ½ at an edge midpoint.
  auto parent_weights = [&](NodeId node, VertexId child_corner) {
    const auto& v = h.corners(node);
    std::array<double, 3> w{0, 0, 0};
    for (int l = 0; l < 3; ++l) {
      if (v[l] == child_corner) {
        w[l] = 1.0;
        return w;
      }
    }
    // The centre child's corner k is the midpoint of the edge opposite corner k.
    const auto& m = h.corners(h.child(node, 3));
    for (int k = 0; k < 3; ++k) {
      if (m[k] == child_corner) {
        w[(k + 1) % 3] = w[(k + 2) % 3] = 0.5;
        return w;
      }
    }
    assert(false && "a child corner is neither a corner nor an edge midpoint of its parent");
    return w;
  };
  for (std::size_t i = n; i-- > 0;) {
    const NodeId node = static_cast<NodeId>(i);
    const double area = node_area[i];
    if (h.is_leaf(node)) {
      const auto& v = h.corners(node);
      // ∫ N_l N_m dA = A/12 (1 + δ_lm)
      const Rgb sum = L[v[0]] + L[v[1]] + L[v[2]];
      for (int l = 0; l < 3; ++l) {
        g[i][l] = area / 12.0 * (L[v[l]] + sum);
        out.corners[i][l] = L[v[l]];
      }
      continue;
    }
    std::array<Rgb, 3> gi{Rgb(0, 0, 0), Rgb(0, 0, 0), Rgb(0, 0, 0)};
    for (int c = 0; c < 4; ++c) {
      const NodeId child = h.child(node, c);
      const auto& cv = h.corners(child);
      for (int m = 0; m < 3; ++m) {
        const auto w = parent_weights(node, cv[m]);
        for (int l = 0; l < 3; ++l) gi[l] += w[l] * g[child][m];
      }
    }
    g[i] = gi;
    // The inverse of the hat functions' mass matrix A/12 [[2,1,1],[1,2,1],[1,1,2]].
    const Rgb total = gi[0] + gi[1] + gi[2];
    std::array<Rgb, 3>& p = out.corners[i];
    for (int l = 0; l < 3; ++l) p[l] = area > 0 ? (3.0 / area) * (4.0 * gi[l] - total) : Rgb(0, 0, 0);
    for (int k = 0; k < 3; ++k) {
      const double mean = (p[0][k] + p[1][k] + p[2][k]) / 3.0;
      const double low = std::min({p[0][k], p[1][k], p[2][k]});
      if (low < 0.0) {
        const double t = mean > 0.0 ? mean / (mean - low) : 0.0;
        for (int l = 0; l < 3; ++l) p[l][k] = std::max(0.0, mean + t * (p[l][k] - mean));
      }
    }
    // L − P = (L − P_child) + (P_child − P) on each child; the second term is
    // linear there, so its largest size is at the child's corners.
    Rgb bound(0, 0, 0);
    for (int c = 0; c < 4; ++c) {
      const NodeId child = h.child(node, c);
      const auto& cv = h.corners(child);
      Rgb off(0, 0, 0);
      for (int m = 0; m < 3; ++m) {
        const auto w = parent_weights(node, cv[m]);
        const Rgb here = w[0] * p[0] + w[1] * p[1] + w[2] * p[2];
        raise_to(off, abs_difference(out.corners[child][m], here));
      }
      raise_to(bound, out.spread[child] + off);
    }
    out.spread[i] = bound;
  }
  out.root_integral.resize(h.num_roots());
  for (std::size_t r = 0; r < out.root_integral.size(); ++r) out.root_integral[r] = g[r][0] + g[r][1] + g[r][2];
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
