#include "mesh/initial_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>
#include <CGAL/boost/graph/properties_TriMesh_ArrayKernelT.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

namespace lhr {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;

// Input point a triangulation vertex was created from; -1 for Steiner points.
struct InputVertex {
  int index = -1;
};

using VertexBase =
    CGAL::Triangulation_vertex_base_with_info_2<InputVertex, Kernel, CGAL::Triangulation_vertex_base_2<Kernel>>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Contact lines may cross each other (two boxes pushed into each other), so
// CGAL constructs intersection points; crossing polygon edges, which mean
// broken input, are caught by counting vertices (mesh_planar).
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;

constexpr double kPi = 3.14159265358979323846;
// Largest smallest-angle bound for which Delaunay refinement provably
// terminates: shape bound B = sin^2(angle) = 0.125 (CGAL Delaunay_mesh_criteria_2).
const double kMaxMinAngleRad = std::asin(std::sqrt(0.125));
// Adjacent input triangles whose normals differ by more than this are kept
// apart by a constraint so the output follows the input's piecewise-linear
// shape; below it the bend changes areas by ~angle^2, far under rounding.
constexpr double kCreaseAngleRad = 1e-9;
// Input triangles thinner than this (smallest angle in radians, about) are
// taken as degenerate.
constexpr double kDegenerateSine = 1e-10;
// Guard against runaway refinement (and memory) on one surface.
constexpr std::size_t kMaxVerticesPerSurface = std::size_t{1} << 24;
// Curved surfaces: CGAL splits edges longer than 4/3 of the target length,
// so a target of 3/4 h keeps remeshed edges at h (Botsch & Kobbelt 2004).
constexpr double kCurvedTargetFraction = 0.75;
// An input edge where the surface bends by more than this (the angle between
// its two faces' normals) stays a line of the initial mesh, so every
// triangle lies in one input polygon's plane there: the path tracer and the
// vertex reference see the input polygons, and a triangle remeshed across a
// bend of δ tilts by up to δ/2 from them, which changes the cosine toward a
// light at incidence θ by about tan θ · δ/2 (2 % at 45° for δ = 2°) and
// moves a light's horizon to another place on the surface. A 32 × 16 UV
// sphere bends 11.25° at every edge; the published Cornell box's warped
// wall 0.33° and a finely tessellated terrain under 1°, and those are still
// coarsened to the minimum density (docs/design.md §4, "Initial meshing").
constexpr double kKeptBendDeg = 2.0;
constexpr unsigned kRemeshIterations = 3;
// A border or bend vertex whose two constrained edges turn by more
// than this stays fixed, so coarsening the line does not cut its corners.
constexpr double kConstraintCornerDeg = 30.0;
// No remeshed triangle may have a vertex closer than this fraction of its
// longest edge to the line through the opposite edge.
constexpr double kDegenerateHeight = 1e-6;

double orient2(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

void check_options(const MeshingOptions& options) {
  if (!(options.max_edge > 0.0) || !std::isfinite(options.max_edge)) {
    throw std::invalid_argument("meshing: max edge length must be a positive finite number, got " +
                                std::to_string(options.max_edge));
  }
  if (!(options.min_angle_deg > 0.0) || !(options.min_angle_deg < 60.0)) {
    throw std::invalid_argument("meshing: minimum angle must be in (0, 60) degrees, got " +
                                std::to_string(options.min_angle_deg));
  }
}

void check_polygons(const Surface& surface) {
  if (surface.polygons.empty()) throw std::runtime_error("has no polygons");
  const int n = static_cast<int>(surface.points.size());
  for (std::size_t p = 0; p < surface.polygons.size(); ++p) {
    const auto& poly = surface.polygons[p];
    if (poly.size() < 3) {
      throw std::runtime_error("polygon " + std::to_string(p) + " has fewer than 3 vertices");
    }
    for (int i : poly) {
      if (i < 0 || i >= n) {
        throw std::runtime_error("polygon " + std::to_string(p) + " refers to point " + std::to_string(i) +
                                 " of " + std::to_string(n));
      }
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(surface.points[i][k])) {
          throw std::runtime_error("point " + std::to_string(i) + " is not finite");
        }
      }
    }
  }
}

// Area-weighted normal (Newell), used when the surface carries none.
Vec3 newell_vector_area(const Surface& surface) {
  Vec3 sum(0, 0, 0);
  for (const auto& poly : surface.polygons) {
    const Vec3& o = surface.points[poly[0]];
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      sum += 0.5 * OpenMesh::cross(surface.points[poly[i]] - o, surface.points[poly[i + 1]] - o);
    }
  }
  return sum;
}

// ---------------------------------------------------------------------------
// Planar surfaces.

// The input polygons split into triangles: the piecewise-linear shape that
// Steiner points are placed on, and the region the mesh must cover.
class InputTriangles {
 public:
  InputTriangles(std::vector<Point2> points2, std::vector<std::array<int, 3>> triangles)
      : points2_(std::move(points2)), triangles_(std::move(triangles)) {
    build_grid();
  }

  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

  struct Location {
    int triangle = -1;
    std::array<double, 3> barycentric{0, 0, 0};
    double min_barycentric = -std::numeric_limits<double>::infinity();
  };

  // The input triangle that contains p best (largest smallest barycentric
  // coordinate); min_barycentric < 0 means p lies outside all of them.
  Location locate(const Point2& p) const {
    Location best;
    const auto& cell = cells_[cell_of(p)];
    for (int t : cell) {
      const auto& tri = triangles_[t];
      const Point2& a = points2_[tri[0]];
      const Point2& b = points2_[tri[1]];
      const Point2& c = points2_[tri[2]];
      const double area = orient2(a, b, c);
      const std::array<double, 3> w{orient2(p, b, c) / area, orient2(a, p, c) / area, orient2(a, b, p) / area};
      const double m = std::min({w[0], w[1], w[2]});
      if (m > best.min_barycentric) best = Location{t, w, m};
    }
    return best;
  }

 private:
  void build_grid() {
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
    double x1 = -x0, y1 = -x0;
    for (const auto& tri : triangles_) {
      for (int i : tri) {
        x0 = std::min(x0, points2_[i].x());
        y0 = std::min(y0, points2_[i].y());
        x1 = std::max(x1, points2_[i].x());
        y1 = std::max(y1, points2_[i].y());
      }
    }
    const double w = std::max(x1 - x0, 1e-300);
    const double h = std::max(y1 - y0, 1e-300);
    const double n = static_cast<double>(triangles_.size());
    nx_ = static_cast<int>(std::clamp(std::ceil(std::sqrt(n * w / h)), 1.0, 512.0));
    ny_ = static_cast<int>(std::clamp(std::ceil(std::sqrt(n * h / w)), 1.0, 512.0));
    x0_ = x0;
    y0_ = y0;
    sx_ = nx_ / w;
    sy_ = ny_ / h;
    cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
    // Slack so points rounded onto a triangle's edge still find it.
    const double pad = 1e-9 * std::hypot(w, h);
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      double tx0 = std::numeric_limits<double>::infinity(), ty0 = tx0, tx1 = -tx0, ty1 = -tx0;
      for (int i : triangles_[t]) {
        tx0 = std::min(tx0, points2_[i].x());
        ty0 = std::min(ty0, points2_[i].y());
        tx1 = std::max(tx1, points2_[i].x());
        ty1 = std::max(ty1, points2_[i].y());
      }
      const int i0 = clamp_x(tx0 - pad), i1 = clamp_x(tx1 + pad);
      const int j0 = clamp_y(ty0 - pad), j1 = clamp_y(ty1 + pad);
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) cells_[static_cast<std::size_t>(j) * nx_ + i].push_back(static_cast<int>(t));
      }
    }
  }
  int clamp_x(double x) const { return std::clamp(static_cast<int>(std::floor((x - x0_) * sx_)), 0, nx_ - 1); }
  int clamp_y(double y) const { return std::clamp(static_cast<int>(std::floor((y - y0_) * sy_)), 0, ny_ - 1); }
  std::size_t cell_of(const Point2& p) const {
    return static_cast<std::size_t>(clamp_y(p.y())) * nx_ + clamp_x(p.x());
  }

  std::vector<Point2> points2_;
  std::vector<std::array<int, 3>> triangles_;
  int nx_ = 1, ny_ = 1;
  double x0_ = 0, y0_ = 0, sx_ = 1, sy_ = 1;
  std::vector<std::vector<int>> cells_;
};

// Splits one polygon (counter-clockwise in the plane) into triangles: a fan
// when every fan triangle is counter-clockwise (then the fan tiles the
// polygon: its wedges around vertex 0 are disjoint), else ear clipping.
// Degenerate (collinear) pieces are dropped.
void triangulate_polygon(const std::vector<int>& poly, const std::vector<Point2>& q, std::size_t polygon_index,
                         std::vector<std::array<int, 3>>& out) {
  bool fan_ok = true;
  for (std::size_t i = 1; i + 1 < poly.size() && fan_ok; ++i) {
    fan_ok = CGAL::orientation(q[poly[0]], q[poly[i]], q[poly[i + 1]]) != CGAL::RIGHT_TURN;
  }
  if (fan_ok) {
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      if (CGAL::orientation(q[poly[0]], q[poly[i]], q[poly[i + 1]]) == CGAL::LEFT_TURN) {
        out.push_back({poly[0], poly[i], poly[i + 1]});
      }
    }
    return;
  }
  std::vector<int> ring = poly;
  while (ring.size() >= 3) {
    const std::size_t n = ring.size();
    bool clipped = false;
    for (std::size_t i = 0; i < n && !clipped; ++i) {
      const int a = ring[(i + n - 1) % n], b = ring[i], c = ring[(i + 1) % n];
      if (CGAL::orientation(q[a], q[b], q[c]) != CGAL::LEFT_TURN) continue;
      bool empty = true;
      for (std::size_t j = 0; j < n && empty; ++j) {
        const int r = ring[j];
        if (r == a || r == b || r == c || q[r] == q[a] || q[r] == q[b] || q[r] == q[c]) continue;
        empty = !(CGAL::orientation(q[a], q[b], q[r]) != CGAL::RIGHT_TURN &&
                  CGAL::orientation(q[b], q[c], q[r]) != CGAL::RIGHT_TURN &&
                  CGAL::orientation(q[c], q[a], q[r]) != CGAL::RIGHT_TURN);
      }
      if (empty) {
        out.push_back({a, b, c});
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
    }
    if (clipped) continue;
    for (std::size_t i = 0; i < n && !clipped; ++i) {
      const int a = ring[(i + n - 1) % n], b = ring[i], c = ring[(i + 1) % n];
      if (CGAL::orientation(q[a], q[b], q[c]) == CGAL::COLLINEAR) {
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
        clipped = true;
      }
    }
    if (!clipped) {
      throw std::runtime_error("polygon " + std::to_string(polygon_index) +
                               " is self-intersecting or not counter-clockwise seen from the surface front");
    }
  }
}

// Faces connected without crossing a constraint are all inside the region
// or all outside it, so each such component is decided as a whole: outside
// if it reaches the unbounded face, else by the area of its faces whose
// centroids fall inside an input triangle. A per-face test would misjudge the
// slivers that rounding leaves along nearly collinear boundary vertices, and
// the mesher, trusting the marks, would then insert circumcentres of such an
// outside sliver ever farther away without end.
void mark_domain(Cdt& cdt, const InputTriangles& input) {
  std::map<Cdt::Face_handle, int> component;
  std::vector<double> inside_area, outside_area;
  std::vector<bool> unbounded;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (component.count(f)) continue;
    const int id = static_cast<int>(inside_area.size());
    inside_area.push_back(0.0);
    outside_area.push_back(0.0);
    unbounded.push_back(false);
    std::vector<Cdt::Face_handle> stack{f};
    component[f] = id;
    while (!stack.empty()) {
      const Cdt::Face_handle g = stack.back();
      stack.pop_back();
      const Point2& a = g->vertex(0)->point();
      const Point2& b = g->vertex(1)->point();
      const Point2& c = g->vertex(2)->point();
      const double area = 0.5 * orient2(a, b, c);
      (input.locate(CGAL::centroid(a, b, c)).min_barycentric >= 0.0 ? inside_area : outside_area)[id] += area;
      for (int k = 0; k < 3; ++k) {
        const Cdt::Face_handle n = g->neighbor(k);
        if (cdt.is_constrained(Cdt::Edge(g, k))) continue;
        if (cdt.is_infinite(n)) {
          unbounded[id] = true;
          continue;
        }
        if (component.count(n)) continue;
        component[n] = id;
        stack.push_back(n);
      }
    }
  }
  for (auto& [f, id] : component) f->set_in_domain(!unbounded[id] && inside_area[id] > outside_area[id]);
}

// CGAL's refine_Delaunay_mesh_2, one point at a time, so that a run that
// leaves the region (which Delaunay refinement never does in exact
// arithmetic, but rounding on degenerate input might) ends with an error
// instead of running forever.
void refine(Cdt& cdt, const Criteria& criteria) {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    x0 = std::min(x0, v->point().x());
    y0 = std::min(y0, v->point().y());
    x1 = std::max(x1, v->point().x());
    y1 = std::max(y1, v->point().y());
  }
  const double pad = 1e-6 * std::hypot(x1 - x0, y1 - y0);
  CGAL::Delaunay_mesher_2<Cdt, Criteria> mesher(cdt, criteria);
  mesher.init(true);
  std::size_t checked = cdt.number_of_vertices();
  while (!mesher.is_refinement_done()) {
    mesher.step_by_step_refine_mesh();
    if (cdt.number_of_vertices() < 2 * checked) continue;
    checked = cdt.number_of_vertices();
    if (checked > kMaxVerticesPerSurface) {
      throw std::runtime_error("needs more than " + std::to_string(kMaxVerticesPerSurface) +
                               " vertices; use a larger --max-edge");
    }
    for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
      const Point2& p = v->point();
      if (!(p.x() >= x0 - pad && p.x() <= x1 + pad && p.y() >= y0 - pad && p.y() <= y1 + pad)) {
        throw std::runtime_error("Delaunay refinement left the surface (degenerate or overlapping polygons?)");
      }
    }
  }
}

// Contact lines turned into constraints on one surface: clipped to its
// region, their ends snapped (within the contact tolerance) onto polygon
// vertices, onto polygon edges (which are split there) and onto each other,
// and pieces lying along a polygon edge dropped. Without the snapping, an end
// a rounding error away from an edge would leave a sliver that Delaunay
// refinement fills with ever smaller triangles.
struct ContactConstraints {
  std::vector<Point2> points;                          // new points, numbered from the surface's point count on
  std::vector<std::pair<int, int>> polygon_edges;      // the polygon constraints, split at contact ends
  std::vector<std::pair<int, int>> contact_edges;
};

// Parameter intervals of segment p0 + t (p1 - p0), t in [0, 1], inside the
// union of the triangles (a point within `slack` of a triangle counts as in).
std::vector<std::pair<double, double>> clip_to_region(const Point2& p0, const Point2& p1,
                                                      const std::vector<Point2>& q,
                                                      const std::vector<std::array<int, 3>>& triangles, double slack) {
  std::vector<std::pair<double, double>> inside;
  const double sx0 = std::min(p0.x(), p1.x()) - slack, sx1 = std::max(p0.x(), p1.x()) + slack;
  const double sy0 = std::min(p0.y(), p1.y()) - slack, sy1 = std::max(p0.y(), p1.y()) + slack;
  for (const auto& tri : triangles) {
    const Point2 &a = q[tri[0]], &b = q[tri[1]], &c = q[tri[2]];
    if (std::max({a.x(), b.x(), c.x()}) < sx0 || std::min({a.x(), b.x(), c.x()}) > sx1 ||
        std::max({a.y(), b.y(), c.y()}) < sy0 || std::min({a.y(), b.y(), c.y()}) > sy1) {
      continue;
    }
    double t0 = 0.0, t1 = 1.0;
    const std::array<std::pair<const Point2*, const Point2*>, 3> edges{{{&a, &b}, {&b, &c}, {&c, &a}}};
    for (const auto& [e0, e1] : edges) {
      // Signed distance to the edge's line, positive inside, along the segment.
      const double len = std::sqrt(CGAL::squared_distance(*e0, *e1));
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
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double l2 = dx * dx + dy * dy;
  const double t = l2 > 0 ? std::clamp(((p.x() - a.x()) * dx + (p.y() - a.y()) * dy) / l2, 0.0, 1.0) : 0.0;
  if (t_out) *t_out = t;
  return std::hypot(p.x() - a.x() - t * dx, p.y() - a.y() - t * dy);
}

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
      if (v < first_new && std::sqrt(CGAL::squared_distance(p, q[v])) <= tolerance) return v;
    }
    for (std::size_t e = 0; e < polygon_edges.size(); ++e) {
      double t = 0.0;
      const Point2 &a = q[polygon_edges[e].first], &b = q[polygon_edges[e].second];
      if (distance_to_segment(p, a, b, &t) > tolerance) continue;
      for (const auto& [s, i] : on_edge[e]) {
        if (std::sqrt(CGAL::squared_distance(p, point(i))) <= tolerance) return i;
      }
      const int i = first_new + static_cast<int>(plan.points.size());
      plan.points.emplace_back(a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y()));
      on_edge[e].emplace_back(t, i);
      edges_at[i].push_back(e);
      return i;
    }
    for (int i : contact_points) {
      if (std::sqrt(CGAL::squared_distance(p, point(i))) <= tolerance) return i;
    }
    const int i = first_new + static_cast<int>(plan.points.size());
    plan.points.push_back(p);
    contact_points.push_back(i);
    return i;
  };

  std::vector<std::pair<int, int>> pieces;
  for (const auto& [p0, p1] : contacts) {
    const double length = std::sqrt(CGAL::squared_distance(p0, p1));
    if (!(length > tolerance)) continue;
    for (const auto& [t0, t1] : clip_to_region(p0, p1, q, triangles, 0.5 * tolerance)) {
      if ((t1 - t0) * length <= tolerance) continue;
      const int a = resolve(p0 + t0 * (p1 - p0));
      const int b = resolve(p0 + t1 * (p1 - p0));
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

TriMesh mesh_planar(const Surface& surface, const MeshingOptions& options, const std::vector<Segment3>& contacts,
                    double contact_tolerance) {
  // Frame (u, v, n), right-handed, so counter-clockwise in (u, v) is
  // counter-clockwise seen from the front.
  const Vec3 vector_area = newell_vector_area(surface);
  Vec3 n = surface.normal;
  if (!(n.norm() > 0.5 && n.norm() < 1.5)) n = vector_area;
  if (!(n.norm() > 0.0)) throw std::runtime_error("polygons have zero area");
  n.normalize();
  if (OpenMesh::dot(vector_area, n) <= 0.0) {
    throw std::runtime_error("polygons face away from the surface normal");
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(n[k]) < std::abs(n[axis])) axis = k;
  }
  Vec3 e(0, 0, 0);
  e[axis] = 1.0;
  const Vec3 u = OpenMesh::cross(n, e).normalized();
  const Vec3 v = OpenMesh::cross(n, u);
  const Vec3 origin = surface.points[surface.polygons[0][0]];

  std::vector<Point2> q(surface.points.size());
  for (std::size_t i = 0; i < surface.points.size(); ++i) {
    const Vec3 d = surface.points[i] - origin;
    q[i] = Point2(OpenMesh::dot(d, u), OpenMesh::dot(d, v));
  }

  // Input triangles, in polygon order.
  std::vector<std::array<int, 3>> triangles;
  double input_area2 = 0.0;
  for (std::size_t p = 0; p < surface.polygons.size(); ++p) {
    const auto& poly = surface.polygons[p];
    double signed_area = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Point2& a = q[poly[i]];
      const Point2& b = q[poly[(i + 1) % poly.size()]];
      signed_area += a.x() * b.y() - a.y() * b.x();
    }
    if (!(signed_area > 0.0)) {
      throw std::runtime_error("polygon " + std::to_string(p) +
                               " is degenerate or not counter-clockwise seen from the surface front");
    }
    const std::size_t first = triangles.size();
    triangulate_polygon(poly, q, p, triangles);
    for (std::size_t t = first; t < triangles.size(); ++t) {
      input_area2 += 0.5 * orient2(q[triangles[t][0]], q[triangles[t][1]], q[triangles[t][2]]);
    }
  }
  // Pieces cut off between collinear polygon vertices are slivers whose
  // normals are rounding noise; they carry no area or shape, so neither the
  // tilt, the crease test nor the point lookup may use them.
  std::erase_if(triangles, [&](const std::array<int, 3>& t) {
    const Point2 &a = q[t[0]], &b = q[t[1]], &c = q[t[2]];
    const double longest =
        std::max({CGAL::squared_distance(a, b), CGAL::squared_distance(b, c), CGAL::squared_distance(c, a)});
    return !(orient2(a, b, c) > kDegenerateSine * longest);
  });
  if (triangles.empty()) throw std::runtime_error("polygons have zero area");

  // Tilt of each input triangle against the frame: a 2D length l is at most
  // l / cos(tilt) in 3D, and angles change by at most 1/cos(tilt) - 1 radians
  // (the 3D triangle projects onto the 2D one).
  std::vector<Vec3> tri_normal(triangles.size());
  double min_cos = 1.0;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    const Vec3& a = surface.points[tri[0]];
    const Vec3 c = OpenMesh::cross(surface.points[tri[1]] - a, surface.points[tri[2]] - a);
    tri_normal[t] = c.normalized();
    const double cos_tilt = OpenMesh::dot(tri_normal[t], n);
    if (!(cos_tilt > 0.5)) {
      throw std::runtime_error("is marked planar but bends by more than 60 degrees; mesh it as a curved surface");
    }
    min_cos = std::min(min_cos, cos_tilt);
  }

  // Constraints: boundary edges (used by exactly one polygon) and creases of
  // the piecewise-linear input inside the region.
  std::map<std::uint64_t, int> polygon_edge_uses;
  for (const auto& poly : surface.polygons) {
    for (std::size_t i = 0; i < poly.size(); ++i) {
      if (poly[i] != poly[(i + 1) % poly.size()]) ++polygon_edge_uses[edge_key(poly[i], poly[(i + 1) % poly.size()])];
    }
  }
  std::vector<std::pair<int, int>> constraints;
  for (const auto& [key, uses] : polygon_edge_uses) {
    if (uses > 2) {
      throw std::runtime_error("edge (" + std::to_string(key >> 32) + "," + std::to_string(key & 0xffffffffu) +
                               ") is shared by " + std::to_string(uses) + " polygons");
    }
    if (uses == 1) constraints.emplace_back(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu));
  }
  std::map<std::uint64_t, std::vector<int>> triangle_edges;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      triangle_edges[edge_key(triangles[t][k], triangles[t][(k + 1) % 3])].push_back(static_cast<int>(t));
    }
  }
  for (const auto& [key, tris] : triangle_edges) {
    if (tris.size() != 2 || (polygon_edge_uses.count(key) && polygon_edge_uses.at(key) == 1)) continue;
    const double c = std::clamp(OpenMesh::dot(tri_normal[tris[0]], tri_normal[tris[1]]), -1.0, 1.0);
    const double s = OpenMesh::cross(tri_normal[tris[0]], tri_normal[tris[1]]).norm();
    if (std::atan2(s, c) > kCreaseAngleRad) {
      constraints.emplace_back(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu));
    }
  }

  std::vector<std::pair<Point2, Point2>> contacts2;
  for (const Segment3& c : contacts) {
    const Vec3 d0 = c[0] - origin, d1 = c[1] - origin;
    contacts2.emplace_back(Point2(OpenMesh::dot(d0, u), OpenMesh::dot(d0, v)),
                           Point2(OpenMesh::dot(d1, u), OpenMesh::dot(d1, v)));
  }
  ContactConstraints plan = plan_contacts(q, triangles, constraints, contacts2, contact_tolerance);
  std::vector<Point2> all_points = q;
  all_points.insert(all_points.end(), plan.points.begin(), plan.points.end());

  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handles(all_points.size());
  // Only constraint ends are inserted: an input vertex inside a flat part
  // carries no shape, and keeping it would force the mesh finer than h
  // (docs/design.md §4: minimum density). Points added for contact lines keep index
  // -1, so their 3D position comes from the input triangles.
  std::vector<bool> used(all_points.size(), false);
  for (const auto& [a, b] : plan.polygon_edges) used[a] = used[b] = true;
  for (const auto& [a, b] : plan.contact_edges) used[a] = used[b] = true;
  for (std::size_t i = 0; i < all_points.size(); ++i) {
    if (!used[i]) continue;
    handles[i] = cdt.insert(all_points[i]);
    if (handles[i]->info().index < 0 && i < surface.points.size()) handles[i]->info().index = static_cast<int>(i);
  }
  const std::size_t inserted = cdt.number_of_vertices();
  for (const auto& [a, b] : plan.polygon_edges) {
    if (handles[a] != handles[b]) cdt.insert_constraint(handles[a], handles[b]);
  }
  // Constraints crossing each other get a vertex at the crossing.
  if (cdt.number_of_vertices() != inserted) throw std::runtime_error("polygon edges cross each other");
  for (const auto& [a, b] : plan.contact_edges) {
    if (handles[a] != handles[b]) cdt.insert_constraint(handles[a], handles[b]);
  }

  // Polygons that exactly cover each other (a duplicated face) leave no
  // boundary edge, so nothing was inserted; CGAL's mesher needs a 2D
  // triangulation and follows null neighbours otherwise.
  if (cdt.dimension() < 2) throw std::runtime_error("has no boundary edge (duplicated or overlapping polygons?)");
  const InputTriangles input(q, triangles);
  mark_domain(cdt, input);

  // Leave room for the tilt: 2D bounds tight enough that the 3D mesh keeps
  // edges <= h and angles >= the requested minimum.
  const double tilt_angle_slack = 1.0 / min_cos - 1.0;
  const double min_angle_2d =
      std::min(options.min_angle_deg * kPi / 180.0 + tilt_angle_slack, kMaxMinAngleRad);
  const double shape_bound = std::pow(std::sin(min_angle_2d), 2);
  const double size_bound_2d = options.max_edge * min_cos * (1.0 - 1e-12);
  refine(cdt, Criteria(shape_bound, size_bound_2d));

  TriMesh mesh;
  std::map<Cdt::Vertex_handle, TriMesh::VertexHandle> to_mesh;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    for (int k = 0; k < 3; ++k) to_mesh.emplace(f->vertex(k), TriMesh::VertexHandle());
  }
  // Vertices in triangulation order (deterministic), not in map order.
  for (auto vit = cdt.finite_vertices_begin(); vit != cdt.finite_vertices_end(); ++vit) {
    const auto it = to_mesh.find(vit);
    if (it == to_mesh.end()) continue;
    Vec3 p;
    if (vit->info().index >= 0) {
      p = surface.points[vit->info().index];
    } else {
      const InputTriangles::Location loc = input.locate(vit->point());
      if (loc.triangle < 0 || loc.min_barycentric < -1e-6) {
        throw std::runtime_error("mesher placed a point outside the surface (overlapping polygons?)");
      }
      std::array<double, 3> w = loc.barycentric;
      double sum = 0.0;
      for (double& x : w) sum += (x = std::max(x, 0.0));
      const auto& tri = input.triangles()[loc.triangle];
      p = (w[0] / sum) * surface.points[tri[0]] + (w[1] / sum) * surface.points[tri[1]] +
          (w[2] / sum) * surface.points[tri[2]];
    }
    it->second = mesh.add_vertex(p);
  }
  double output_area2 = 0.0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    output_area2 += 0.5 * orient2(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
    const auto fh = mesh.add_face(to_mesh.at(f->vertex(0)), to_mesh.at(f->vertex(1)), to_mesh.at(f->vertex(2)));
    if (!fh.is_valid()) {
      throw std::runtime_error("the surface's region is not manifold (it touches itself at a vertex)");
    }
  }
  if (mesh.n_faces() == 0) throw std::runtime_error("meshing produced no triangles");
  if (std::abs(output_area2 - input_area2) > 1e-9 * input_area2) {
    throw std::runtime_error("polygons overlap or leave gaps (meshed area " + std::to_string(output_area2) +
                             " vs polygon area " + std::to_string(input_area2) + ")");
  }
  return mesh;
}

// ---------------------------------------------------------------------------
// Curved surfaces.

// What the caller's checkpoint threw, carried past the meshing code's own
// `catch (const std::exception&)` (the contact-line fallback, the surface's
// name added to errors) and rethrown unchanged by mesh_surface.
struct CheckpointThrew {
  std::exception_ptr thrown;
};

// CGAL's remeshing has no hook of its own; it reads every vertex position
// through the point map, so the map calls the checkpoint every so many reads.
class MeshingCheckpoint {
 public:
  explicit MeshingCheckpoint(const std::function<void()>& checkpoint) : checkpoint_(checkpoint) {}
  void operator()() const {
    if (!checkpoint_) return;
    try {
      checkpoint_();
    } catch (...) {
      throw CheckpointThrew{std::current_exception()};
    }
  }
  void tick() {
    if (++reads_ % kReadsPerCheck == 0) (*this)();
  }

 private:
  static constexpr std::uint64_t kReadsPerCheck = 1 << 14;
  const std::function<void()>& checkpoint_;
  std::uint64_t reads_ = 0;
};

// Reads and writes OpenMesh points as CGAL points in double precision; the
// adapter's own map rounds written points to float.
struct PointMap {
  using key_type = boost::graph_traits<TriMesh>::vertex_descriptor;
  using value_type = Kernel::Point_3;
  using reference = Kernel::Point_3;
  using category = boost::read_write_property_map_tag;
  TriMesh* mesh = nullptr;
  MeshingCheckpoint* checkpoint = nullptr;

  friend value_type get(const PointMap& m, key_type v) {
    if (m.checkpoint != nullptr) m.checkpoint->tick();
    const Vec3& p = m.mesh->point(v);
    return value_type(p[0], p[1], p[2]);
  }
  friend void put(const PointMap& m, key_type v, const value_type& p) {
    m.mesh->set_point(v, Vec3(p.x(), p.y(), p.z()));
  }
};

// Constrained-or-not flags on OpenMesh properties, so they follow the mesh
// through splits; CGAL's dynamic bool maps do not compile against OpenMesh's
// std::vector<bool> storage.
struct EdgeFlagMap {
  using key_type = boost::graph_traits<TriMesh>::edge_descriptor;
  using value_type = bool;
  using reference = bool;
  using category = boost::read_write_property_map_tag;
  TriMesh* mesh = nullptr;
  OpenMesh::EPropHandleT<unsigned char> prop;

  friend bool get(const EdgeFlagMap& m, key_type e) {
    return m.mesh->property(m.prop, m.mesh->edge_handle(e.halfedge())) != 0;
  }
  friend void put(const EdgeFlagMap& m, key_type e, bool value) {
    m.mesh->property(m.prop, m.mesh->edge_handle(e.halfedge())) = value ? 1 : 0;
  }
};

struct VertexFlagMap {
  using key_type = boost::graph_traits<TriMesh>::vertex_descriptor;
  using value_type = bool;
  using reference = bool;
  using category = boost::read_write_property_map_tag;
  TriMesh* mesh = nullptr;
  OpenMesh::VPropHandleT<unsigned char> prop;

  friend bool get(const VertexFlagMap& m, key_type v) { return m.mesh->property(m.prop, v) != 0; }
  friend void put(const VertexFlagMap& m, key_type v, bool value) { m.mesh->property(m.prop, v) = value ? 1 : 0; }
};

double edge_length(const TriMesh& mesh, boost::graph_traits<TriMesh>::edge_descriptor e) {
  return mesh.calc_edge_length(mesh.edge_handle(e.halfedge()));
}

// `fixed` vertices are neither moved nor removed: the ends of seam edges,
// which another surface shares, and corners of the open border.
void remesh(TriMesh& mesh, double h, const std::vector<TriMesh::VertexHandle>& fixed, MeshingCheckpoint& checkpoint) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();

  const PointMap points{&mesh, &checkpoint};
  EdgeFlagMap constrained_edge;
  constrained_edge.mesh = &mesh;
  VertexFlagMap constrained_vertex;
  constrained_vertex.mesh = &mesh;
  mesh.add_property(constrained_edge.prop);
  mesh.add_property(constrained_vertex.prop);
  for (const auto e : edges(mesh)) put(constrained_edge, e, CGAL::is_border(e, mesh));
  PMP::detect_sharp_edges(mesh, kKeptBendDeg, constrained_edge, CGAL::parameters::vertex_point_map(points));
  for (const auto v : vertices(mesh)) put(constrained_vertex, v, false);
  for (const auto v : fixed) put(constrained_vertex, v, true);
  // Constrained edges are split and collapsed along themselves, so the
  // border and the bends keep their polyline; vertices where such
  // lines meet or turn are kept where they are.
  for (const auto v : mesh.vertices()) {
    std::vector<Vec3> directions;
    for (const auto he : mesh.voh_range(v)) {
      if (get(constrained_edge, edge(he, mesh))) directions.push_back(mesh.calc_edge_vector(he).normalized());
    }
    if (directions.empty()) continue;
    if (directions.size() != 2 ||
        OpenMesh::dot(directions[0], -directions[1]) < std::cos(kConstraintCornerDeg * kPi / 180.0)) {
      put(constrained_vertex, v, true);
    }
  }

  const double target_length = kCurvedTargetFraction * h;
  PMP::isotropic_remeshing(faces(mesh), target_length, mesh,
                           CGAL::parameters::number_of_iterations(kRemeshIterations)
                               .edge_is_constrained_map(constrained_edge)
                               .vertex_is_constrained_map(constrained_vertex)
                               .protect_constraints(false)
                               .vertex_point_map(points));

  // Smoothing can stretch an edge past h; split what remains.
  std::vector<boost::graph_traits<TriMesh>::edge_descriptor> to_split;
  for (int round = 0; round < 8; ++round) {
    to_split.clear();
    for (const auto e : edges(mesh)) {
      if (edge_length(mesh, e) > h) to_split.push_back(e);
    }
    if (to_split.empty()) break;
    checkpoint();
    PMP::split_long_edges(to_split, h * (1.0 - 1e-12), mesh,
                          CGAL::parameters::edge_is_constrained_map(constrained_edge).vertex_point_map(points));
  }
  mesh.remove_property(constrained_edge.prop);
  mesh.remove_property(constrained_vertex.prop);
}

TriMesh mesh_curved(const Surface& surface, const MeshingOptions& options) {
  const double h = options.max_edge;
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> handle(surface.points.size());
  for (std::size_t p = 0; p < surface.polygons.size(); ++p) {
    const auto& poly = surface.polygons[p];
    for (int i : poly) {
      if (!handle[i].is_valid()) handle[i] = mesh.add_vertex(surface.points[i]);
    }
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      const auto fh = mesh.add_face(handle[poly[0]], handle[poly[i]], handle[poly[i + 1]]);
      if (!fh.is_valid()) {
        throw std::runtime_error("polygon " + std::to_string(p) +
                                 " makes the surface non-manifold or flips its orientation");
      }
    }
  }
  for (const auto f : mesh.faces()) {
    if (!(mesh.calc_face_normal(f).norm() > 0.0)) {
      throw std::runtime_error("has a zero-area polygon; remove it or merge its vertices");
    }
  }
  std::vector<TriMesh::VertexHandle> fixed;
  for (const auto& [a, b] : surface.seam_edges) {
    fixed.push_back(handle.at(a));
    fixed.push_back(handle.at(b));
  }
  MeshingCheckpoint checkpoint(options.checkpoint);
  checkpoint();
  remesh(mesh, h, fixed, checkpoint);
  checkpoint();
  mesh.garbage_collection();
  // CGAL's Euler operations do not keep OpenMesh's invariant that a boundary
  // vertex's outgoing halfedge is a boundary one; is_boundary(v) relies on it.
  for (const auto v : mesh.vertices()) mesh.adjust_outgoing_halfedge(v);
  for (const auto e : mesh.edges()) {
    if (mesh.calc_edge_length(e) > h * (1.0 + 1e-9)) {
      throw std::runtime_error("remeshing left an edge longer than the maximum edge length");
    }
  }
  // Embree and the form factors need a normal on every triangle.
  for (const auto f : mesh.faces()) {
    double longest = 0.0;
    for (const auto he : mesh.fh_range(f)) longest = std::max(longest, mesh.calc_edge_length(he));
    if (!(2.0 * mesh.calc_face_area(f) > kDegenerateHeight * longest * longest)) {
      throw std::runtime_error("remeshing left a degenerate triangle; give a smaller --max-edge");
    }
  }
  if (mesh.n_faces() == 0) throw std::runtime_error("remeshing produced no triangles");
  return mesh;
}

}  // namespace

double default_max_edge(const Scene& scene) {
  const double diagonal = scene_bounds(scene).diagonal();
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) {
    throw std::runtime_error("scene '" + scene.source +
                             "' has no extent, so no default maximum edge length; give --max-edge");
  }
  // docs/design.md §4: the minimum density h defaults to a fraction of the scene size.
  return diagonal / 20.0;
}

TriMesh mesh_surface(const Surface& surface, const MeshingOptions& options, const std::vector<Segment3>& contacts,
                     double contact_tolerance) {
  check_options(options);
  try {
    check_polygons(surface);
    if (!surface.planar) return mesh_curved(surface, options);
    if (!contacts.empty()) {
      // Contact lines sharpen the mesh but are not needed for a valid one:
      // should they defeat the mesher (near-degenerate crossings), the
      // surface is meshed as if nothing touched it.
      try {
        return mesh_planar(surface, options, contacts, contact_tolerance);
      } catch (const std::exception&) {
      }
    }
    return mesh_planar(surface, options, {}, 0.0);
  } catch (const CheckpointThrew& stop) {
    std::rethrow_exception(stop.thrown);
  } catch (const std::exception& e) {
    throw std::runtime_error("surface '" + surface.name + "': " + e.what());
  }
}

}  // namespace lhr
