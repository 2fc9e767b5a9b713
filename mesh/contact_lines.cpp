#include "mesh/contact_lines.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <set>
#include <utility>

#include "mesh/edge_key.hpp"

namespace lhr {

namespace {

// Relative to the scene's size; ten times the lift of a light drawn on its
// ceiling (mesh/surfaces.cpp), far below any gap a picture shows.
constexpr double kContactRelative = 1e-3;

struct SurfaceBox {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi = -lo;
};

SurfaceBox bounds_of(const Surface& s) {
  SurfaceBox b;
  for (const Vec3& p : s.points) {
    b.lo.minimize(p);
    b.hi.maximize(p);
  }
  return b;
}

bool overlap(const SurfaceBox& a, const SurfaceBox& b, double slack) {
  for (int k = 0; k < 3; ++k) {
    if (a.hi[k] + slack < b.lo[k] || b.hi[k] + slack < a.lo[k]) return false;
  }
  return true;
}

// The segments where `other` meets the plane of `planar` (unit normal n,
// n . x = offset), appended to out.
void add_contacts(const Surface& planar, double offset, const Surface& other, double tolerance,
                  std::vector<Segment3>& out) {
  const Vec3& n = planar.normal;
  std::vector<double> d(other.points.size());
  std::vector<int> side(other.points.size());
  for (std::size_t i = 0; i < other.points.size(); ++i) {
    d[i] = OpenMesh::dot(n, other.points[i]) - offset;
    side[i] = d[i] > tolerance ? 1 : (d[i] < -tolerance ? -1 : 0);
  }
  const auto on_plane = [&](int i) { return other.points[i] - d[i] * n; };
  std::set<std::uint64_t> taken;
  for (const auto& poly : other.polygons) {
    bool front = false, back = false;
    for (int i : poly) {
      front |= side[i] > 0;
      back |= side[i] < 0;
    }
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const int a = poly[k], b = poly[(k + 1) % poly.size()];
      if (side[a] != 0 || side[b] != 0) continue;
      const std::uint64_t key = edge_key(a, b);
      // An edge on the plane bounds what lies on it when its polygon rises
      // in front (the foot of a box). The outline of a surface lying flat on
      // the plane (a light drawn on its ceiling, lifted a hair in front) is
      // not one: the ceiling darkens toward it only within that hair, and a
      // node on the outline holding that limit shades a whole element
      // beside the light dark (a ring around every lamp of two rooms).
      if (!front) continue;
      if (taken.insert(key).second) out.push_back({on_plane(a), on_plane(b)});
    }
    if (!(front && back)) continue;
    // The polygon passes through the plane: where each fan triangle crosses.
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
      const std::array<int, 3> t{poly[0], poly[k], poly[k + 1]};
      std::vector<Vec3> ends;
      for (int j = 0; j < 3; ++j) {
        const int a = t[j], b = t[(j + 1) % 3];
        if (side[a] == 0) ends.push_back(on_plane(a));
        if (side[a] * side[b] < 0) {
          const double w = d[a] / (d[a] - d[b]);
          const Vec3 p = other.points[a] + w * (other.points[b] - other.points[a]);
          ends.push_back(p - (OpenMesh::dot(n, p) - offset) * n);
        }
      }
      if (ends.size() == 2) out.push_back({ends[0], ends[1]});
    }
  }
}

}  // namespace

double contact_tolerance(const std::vector<Surface>& surfaces) {
  SurfaceBox all;
  double magnitude = 0.0;
  for (const Surface& s : surfaces) {
    for (const Vec3& p : s.points) {
      all.lo.minimize(p);
      all.hi.maximize(p);
      magnitude = std::max({magnitude, std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
    }
  }
  if (surfaces.empty()) return 0.0;
  return kContactRelative * std::max((all.hi - all.lo).norm(), magnitude);
}

std::vector<std::vector<Segment3>> find_contact_lines(const std::vector<Surface>& surfaces, double tolerance) {
  const std::size_t count = surfaces.size();
  std::vector<std::vector<Segment3>> contacts(count);
  if (!(tolerance > 0.0)) return contacts;
  std::vector<SurfaceBox> box(count);
  for (std::size_t s = 0; s < count; ++s) box[s] = bounds_of(surfaces[s]);

  // Pairs whose boxes meet, by a sweep along x.
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return box[a].lo[0] < box[b].lo[0] || (box[a].lo[0] == box[b].lo[0] && a < b);
  });
  std::vector<std::vector<std::size_t>> near(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t a = order[i];
    for (std::size_t j = i + 1; j < count && box[order[j]].lo[0] <= box[a].hi[0] + tolerance; ++j) {
      const std::size_t b = order[j];
      if (!overlap(box[a], box[b], tolerance)) continue;
      near[a].push_back(b);
      near[b].push_back(a);
    }
  }

  for (std::size_t s = 0; s < count; ++s) {
    const Surface& planar = surfaces[s];
    if (!planar.planar || near[s].empty()) continue;
    double offset = 0.0;
    for (const Vec3& p : planar.points) offset += OpenMesh::dot(planar.normal, p);
    offset /= static_cast<double>(planar.points.size());
    std::sort(near[s].begin(), near[s].end());
    for (std::size_t o : near[s]) {
      add_contacts(planar, offset, surfaces[o], tolerance, contacts[s]);
    }
  }
  return contacts;
}

}  // namespace lhr
