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

// Where contact ends land, each within the tolerance: on a polygon vertex,
// on a polygon edge (a new point there, which splits the edge), on an
// earlier contact end, or else at a new point of their own. New points are
// appended to `points`, numbered from the surface's point count on.
class EndSnapper {
 public:
  EndSnapper(const std::vector<Point2>& q, const std::vector<std::pair<int, int>>& polygon_edges, double tolerance,
             std::vector<Point2>& points)
      : q_(q), polygon_edges_(polygon_edges), tolerance_(tolerance), points_(points),
        first_new_(static_cast<int>(q.size())), on_edge_(polygon_edges.size()) {
    for (std::size_t e = 0; e < polygon_edges.size(); ++e) {
      edges_at_[polygon_edges[e].first].push_back(e);
      edges_at_[polygon_edges[e].second].push_back(e);
    }
  }

  const Point2& point(int i) const { return i < first_new_ ? q_[i] : points_[i - first_new_]; }

  int resolve(const Point2& p) {
    for (const auto& [v, edges] : edges_at_) {
      if (v < first_new_ && distance(p, q_[v]) <= tolerance_) return v;
    }
    for (std::size_t e = 0; e < polygon_edges_.size(); ++e) {
      double t = 0.0;
      const Point2 &a = q_[polygon_edges_[e].first], &b = q_[polygon_edges_[e].second];
      if (distance_to_segment(p, a, b, &t) > tolerance_) continue;
      for (const auto& [s, i] : on_edge_[e]) {
        if (distance(p, point(i)) <= tolerance_) return i;
      }
      const int i = first_new_ + static_cast<int>(points_.size());
      points_.push_back(Point2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
      on_edge_[e].emplace_back(t, i);
      edges_at_[i].push_back(e);
      return i;
    }
    for (int i : contact_points_) {
      if (distance(p, point(i)) <= tolerance_) return i;
    }
    const int i = first_new_ + static_cast<int>(points_.size());
    points_.push_back(p);
    contact_points_.push_back(i);
    return i;
  }

  // Whether a and b lie on one polygon edge (a piece between them runs along it).
  bool along_polygon_edge(int a, int b) const {
    const auto ea = edges_at_.find(a), eb = edges_at_.find(b);
    bool along = false;
    if (ea != edges_at_.end() && eb != edges_at_.end()) {
      for (std::size_t e : ea->second) along |= std::find(eb->second.begin(), eb->second.end(), e) != eb->second.end();
    }
    return along;
  }

  // The polygon edges, split at the points snapped onto them.
  std::vector<std::pair<int, int>> split_polygon_edges() {
    std::vector<std::pair<int, int>> out;
    for (std::size_t e = 0; e < polygon_edges_.size(); ++e) {
      auto& chain = on_edge_[e];
      if (chain.empty()) {
        out.push_back(polygon_edges_[e]);
        continue;
      }
      std::sort(chain.begin(), chain.end());
      int from = polygon_edges_[e].first;
      for (const auto& [t, i] : chain) {
        out.emplace_back(from, i);
        from = i;
      }
      out.emplace_back(from, polygon_edges_[e].second);
    }
    return out;
  }

 private:
  const std::vector<Point2>& q_;
  const std::vector<std::pair<int, int>>& polygon_edges_;
  double tolerance_;
  std::vector<Point2>& points_;
  int first_new_;
  // Points on each polygon edge besides its ends, with their parameters.
  std::vector<std::vector<std::pair<double, int>>> on_edge_;
  std::vector<int> contact_points_;  // new points not on a polygon edge
  // For a point: the polygon edges it lies on (to drop pieces along one).
  std::map<int, std::vector<std::size_t>> edges_at_;
};

// The contact segments clipped to the region, as pairs of snapped ends,
// without those along a polygon edge; sorted, each once.
std::vector<std::pair<int, int>> contact_pieces(const std::vector<std::pair<Point2, Point2>>& contacts,
                                                const std::vector<Point2>& q,
                                                const std::vector<std::array<int, 3>>& triangles, double tolerance,
                                                EndSnapper& snapper) {
  std::vector<std::pair<int, int>> pieces;
  for (const auto& [p0, p1] : contacts) {
    const double length = distance(p0, p1);
    if (!(length > tolerance)) continue;
    for (const auto& [t0, t1] : clip_to_region(p0, p1, q, triangles, 0.5 * tolerance)) {
      if ((t1 - t0) * length <= tolerance) continue;
      const int a = snapper.resolve(lerp(p0, p1, t0));
      const int b = snapper.resolve(lerp(p0, p1, t1));
      if (a == b) continue;
      if (!snapper.along_polygon_edge(a, b)) pieces.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(pieces.begin(), pieces.end());
  pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
  return pieces;
}

// A contact end on another piece (one box's corner against another's side)
// splits that piece.
std::vector<std::pair<int, int>> split_at_ends(const std::vector<std::pair<int, int>>& pieces,
                                               const EndSnapper& snapper, double tolerance) {
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
      if (distance_to_segment(snapper.point(k), snapper.point(a), snapper.point(b), &t) <= tolerance && t > 0.0 &&
          t < 1.0) {
        chain.emplace_back(t, k);
      }
    }
    std::sort(chain.begin(), chain.end());
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      const int u = chain[i].second, v = chain[i + 1].second;
      if (u != v) contact_edges.emplace(std::min(u, v), std::max(u, v));
    }
  }
  return {contact_edges.begin(), contact_edges.end()};
}

}  // namespace

ContactConstraints plan_contacts(const std::vector<Point2>& q, const std::vector<std::array<int, 3>>& triangles,
                                 const std::vector<std::pair<int, int>>& polygon_edges,
                                 const std::vector<std::pair<Point2, Point2>>& contacts, double tolerance) {
  ContactConstraints plan;
  EndSnapper snapper(q, polygon_edges, tolerance, plan.points);
  plan.contact_edges = split_at_ends(contact_pieces(contacts, q, triangles, tolerance, snapper), snapper, tolerance);
  plan.polygon_edges = snapper.split_polygon_edges();
  return plan;
}

}  // namespace lhr
