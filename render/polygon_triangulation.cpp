#include "render/polygon_triangulation.hpp"

#include <cstddef>

namespace lhr {

namespace {

double orient2(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

}  // namespace

std::optional<std::vector<std::array<int, 3>>> triangulate_planar_polygon(const std::vector<std::array<double, 2>>& q) {
  const int n = static_cast<int>(q.size());
  std::vector<std::array<int, 3>> out;
  bool fan_ok = true;
  for (int i = 1; i + 1 < n && fan_ok; ++i) fan_ok = orient2(q[0], q[i], q[i + 1]) >= 0;
  if (fan_ok) {
    for (int i = 1; i + 1 < n; ++i) {
      if (orient2(q[0], q[i], q[i + 1]) > 0) out.push_back({0, i, i + 1});
    }
    return out;
  }
  std::vector<int> ring(n);
  for (int i = 0; i < n; ++i) ring[i] = i;
  while (ring.size() >= 3) {
    const std::size_t m = ring.size();
    bool clipped = false;
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const int a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      if (!(orient2(q[a], q[b], q[c]) > 0)) continue;
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        const int r = ring[j];
        if (r == a || r == b || r == c || q[r] == q[a] || q[r] == q[b] || q[r] == q[c]) continue;
        empty = !(orient2(q[a], q[b], q[r]) >= 0 && orient2(q[b], q[c], q[r]) >= 0 && orient2(q[c], q[a], q[r]) >= 0);
      }
      if (empty) {
        out.push_back({a, b, c});
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
    }
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const int a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      if (orient2(q[a], q[b], q[c]) == 0) {
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
    }
    if (!clipped) return std::nullopt;
  }
  return out;
}

}  // namespace lhr
