#include "mesh/contact_constraints.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <set>

namespace lhr {

namespace {

// Parameter intervals of segment p0 + t (p1 - p0), t in [0, 1], inside the
// union of the triangles (a point within `slack` of a triangle counts as in).
std::vector<std::pair<double, double>> clip_to_region(const Point2& p0, const Point2& p1,
                                                      const std::vector<Point2>& q,
                                                      const std::vector<std::array<int, 3>>& triangles, double slack) {
  std::vector<std::pair<double, double>> inside;
  const double sx0 = std::min(p0.x, p1.x) - slack, sx1 = std::max(p0.x, p1.x) + slack;
  const double sy0 = std::min(p0.y, p1.y) - slack, sy1 = std::max(p0.y, p1.y) + slack;
  for (const auto& tri : triangles) {
    const Point2 &a = q[tri[0]], &b = q[tri[1]], &c = q[tri[2]];
    if (std::max({a.x, b.x, c.x}) < sx0 || std::min({a.x, b.x, c.x}) > sx1 ||
        std::max({a.y, b.y, c.y}) < sy0 || std::min({a.y, b.y, c.y}) > sy1) {
      continue;
    }
    double t0 = 0.0, t1 = 1.0;
    const std::array<std::pair<const Point2*, const Point2*>, 3> edges{{{&a, &b}, {&b, &c}, {&c, &a}}};
    for (const auto& [e0, e1] : edges) {
      // Signed distance to the edge's line, positive inside, along the segment.
      const double len = distance(*e0, *e1);
      const double f0 = orient2(*e0, *e1, p0) / len + slack;
      const double f1 = orient2(*e0, *e1, p1) / len + slack;
      if (f0 < 0 && f1 < 0) {
        t0 = 1.0;
        t1 = 0.0;
        break;
      }
      if (f0 < 0) t0 = std::max(t0, f0 / (f0 - f1));
      if (f1 < 0) t1 = std::min(t1, f0 / (f0 - f1));
    }
    if (t1 > t0) inside.emplace_back(t0, t1);
  }
  std::sort(inside.begin(), inside.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& piece : inside) {
    if (!merged.empty() && piece.first <= merged.back().second + 1e-12) {
      merged.back().second = std::max(merged.back().second, piece.second);
    } else {
      merged.push_back(piece);
    }
  }
  return merged;
}

double distance_to_segment(const Point2& p, const Point2& a, const Point2& b, double* t_out) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
  if (t_out) *t_out = t;
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

}  // namespace

ContactConstraints plan_contacts(const std::vector<Point2>& q, const std::vector<std::array<int, 3>>& triangles,
                                 const std::vector<std::pair<int, int>>& polygon_edges,
                                 const std::vector<std::pair<Point2, Point2>>& contacts, double tolerance) {
  ContactConstraints plan;
  const int first_new = static_cast<int>(q.size());
  const auto point = [&](int i) -> const Point2& { return i < first_new ? q[i] : plan.points[i - first_new]; };
  // Points on each polygon edge besides its ends, with their parameters.
  std::vector<std::vector<std::pair<double, int>>> on_edge(polygon_edges.size());
  std::vector<int> contact_points;  // new points not on a polygon edge
  // For a point: the polygon edges it lies on (to drop pieces along one).
  std::map<int, std::vector<std::size_t>> edges_at;
  for (std::size_t e = 0; e < polygon_edges.size(); ++e) {
    edges_at[polygon_edges[e].first].push_back(e);
    edges_at[polygon_edges[e].second].push_back(e);
  }
  const auto resolve = [&](const Point2& p) -> int {
    for (const auto& [v, edges] : edges_at) {
      if (v < first_new && distance(p, q[v]) <= tolerance) return v;
    }
    for (std::size_t e = 0; e < polygon_edges.size(); ++e) {
      double t = 0.0;
      const Point2 &a = q[polygon_edges[e].first], &b = q[polygon_edges[e].second];
      if (distance_to_segment(p, a, b, &t) > tolerance) continue;
      for (const auto& [s, i] : on_edge[e]) {
        if (distance(p, point(i)) <= tolerance) return i;
      }
      const int i = first_new + static_cast<int>(plan.points.size());
      plan.points.push_back(Point2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
      on_edge[e].emplace_back(t, i);
      edges_at[i].push_back(e);
      return i;
    }
    for (int i : contact_points) {
      if (distance(p, point(i)) <= tolerance) return i;
    }
    const int i = first_new + static_cast<int>(plan.points.size());
    plan.points.push_back(p);
    contact_points.push_back(i);
    return i;
  };

  std::vector<std::pair<int, int>> pieces;
  for (const auto& [p0, p1] : contacts) {
    const double length = distance(p0, p1);
    if (!(length > tolerance)) continue;
    for (const auto& [t0, t1] : clip_to_region(p0, p1, q, triangles, 0.5 * tolerance)) {
      if ((t1 - t0) * length <= tolerance) continue;
      const int a = resolve(lerp(p0, p1, t0));
      const int b = resolve(lerp(p0, p1, t1));
      if (a == b) continue;
      const auto ea = edges_at.find(a), eb = edges_at.find(b);
      bool along_polygon_edge = false;
      if (ea != edges_at.end() && eb != edges_at.end()) {
        for (std::size_t e : ea->second) {
          along_polygon_edge |= std::find(eb->second.begin(), eb->second.end(), e) != eb->second.end();
        }
      }
      if (!along_polygon_edge) pieces.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(pieces.begin(), pieces.end());
  pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());

  // A contact end on another piece (one box's corner against another's
  // side) splits that piece.
  std::vector<int> ends;
  for (const auto& [a, b] : pieces) {
    ends.push_back(a);
    ends.push_back(b);
  }
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  std::set<std::pair<int, int>> contact_edges;
  for (const auto& [a, b] : pieces) {
    std::vector<std::pair<double, int>> chain{{0.0, a}, {1.0, b}};
    for (int k : ends) {
      if (k == a || k == b) continue;
      double t = 0.0;
      if (distance_to_segment(point(k), point(a), point(b), &t) <= tolerance && t > 0.0 && t < 1.0) {
        chain.emplace_back(t, k);
      }
    }
    std::sort(chain.begin(), chain.end());
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      const int u = chain[i].second, v = chain[i + 1].second;
      if (u != v) contact_edges.emplace(std::min(u, v), std::max(u, v));
    }
  }
  plan.contact_edges.assign(contact_edges.begin(), contact_edges.end());

  for (std::size_t e = 0; e < polygon_edges.size(); ++e) {
    auto& chain = on_edge[e];
    if (chain.empty()) {
      plan.polygon_edges.push_back(polygon_edges[e]);
      continue;
    }
    std::sort(chain.begin(), chain.end());
    int from = polygon_edges[e].first;
    for (const auto& [t, i] : chain) {
      plan.polygon_edges.emplace_back(from, i);
      from = i;
    }
    plan.polygon_edges.emplace_back(from, polygon_edges[e].second);
  }
  return plan;
}

}  // namespace lhr
