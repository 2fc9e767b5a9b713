#include "radiosity/form_factor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace lhr {

namespace {

// Relative distance (to the polygon's size) under which x counts as lying on
// the shooter's plane or boundary, where the contour integrand is singular.
constexpr double kSingularTolerance = 1e-9;
// Relative step along the approach direction used to take the limit there.
// The form factor is Lipschitz along a path inside the receiver, so the
// error is of this order.
constexpr double kApproachStep = 1e-8;
// Height above the shooter's plane, relative to its size, that a limit path
// must reach to count as in front of it (far below kApproachStep, far above
// rounding).
constexpr double kPlaneRounding = 1e-12;

Vec3 newell_normal(std::span<const Vec3> polygon) {
  Vec3 n(0, 0, 0);
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % polygon.size()];
    n += OpenMesh::cross(a, b);
  }
  return n;
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.sqrnorm();
  const double t = len2 > 0 ? std::clamp(OpenMesh::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Sutherland–Hodgman against the half-space n·(p − x) ≥ 0: cosθx < 0 carries no energy,
// and Lambert's formula holds only for a polygon wholly above the tangent plane.
// Each input edge gives at most two output vertices; `out` holds 2 × size.
std::size_t clip_above(std::span<const Vec3> polygon, const Vec3& x, const Vec3& n, Vec3* out) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % polygon.size()];
    const double da = OpenMesh::dot(n, a - x);
    const double db = OpenMesh::dot(n, b - x);
    if (da >= 0) out[count++] = a;
    if ((da >= 0) != (db >= 0)) out[count++] = a + (da / (da - db)) * (b - a);
  }
  return count;
}

// Lambert: F = −1/(2π) Σ_edges β_i (n · (R_i × R_{i+1})) / |R_i × R_{i+1}|
// for vertices counter-clockwise from the front (the minus makes front-facing positive).
// One edge's term β (n · (R_a × R_b)) / |R_a × R_b|. Swapping a and b negates
// it exactly: the cross product's components change sign, its norm and the
// dot product do not change (shared_edge_form_factors relies on this).
double edge_term(const Vec3& x, const Vec3& n, const Vec3& from, const Vec3& to) {
  const Vec3 a = from - x;
  const Vec3 b = to - x;
  const Vec3 c = OpenMesh::cross(a, b);
  const double c_norm = c.norm();
  // x collinear with the edge: β is 0 or the edge is degenerate; the term vanishes.
  if (!(c_norm > 1e-300)) return 0.0;
  const double beta = std::atan2(c_norm, OpenMesh::dot(a, b));
  return beta * OpenMesh::dot(n, c) / c_norm;
}

double contour_integral(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon) {
  double sum = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) sum += edge_term(x, n, polygon[i], polygon[(i + 1) % polygon.size()]);
  return -sum / (2.0 * M_PI);
}

// What decides how a polygon's form factor from x is taken: its unit
// normal and size, x's height over its plane, and whether x lies on its
// plane or next to an edge, where the contour integrand is singular and a
// limit is taken instead (point_polygon_form_factor). One function, so the
// shared-edge path decides exactly as the general one does.
struct PolygonFrame {
  bool degenerate = true;  // zero area: no form factor
  Vec3 normal{0, 0, 0};
  double size = 0.0;
  double height = 0.0;
  bool singular = false;
};

PolygonFrame frame_of(const Vec3& x, std::span<const Vec3> polygon) {
  PolygonFrame f;
  const Vec3 area_normal = newell_normal(polygon);
  const double twice_area = area_normal.norm();
  if (!(twice_area > 0)) return f;
  f.degenerate = false;
  f.normal = area_normal / twice_area;
  double size2 = 0.0;
  for (const Vec3& p : polygon) size2 = std::max(size2, (p - polygon[0]).sqrnorm());
  f.size = std::sqrt(size2);
  const double tolerance = kSingularTolerance * f.size;
  f.height = OpenMesh::dot(f.normal, x - polygon[0]);
  // Every edge lies within `size` of polygon[0]: from farther than twice
  // that, x is farther than `size` (≫ tolerance) from each of them.
  const auto near_an_edge = [&] {
    if ((x - polygon[0]).sqrnorm() > 4.0 * size2) return false;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      if (distance_to_segment(x, polygon[i], polygon[(i + 1) % polygon.size()]) <= tolerance) return true;
    }
    return false;
  };
  f.singular = std::abs(f.height) <= tolerance || near_an_edge();
  return f;
}

// Wholly above x's tangent plane: the polygon is its own clip.
bool wholly_above(std::span<const Vec3> polygon, const Vec3& x, const Vec3& n) {
  return std::all_of(polygon.begin(), polygon.end(), [&](const Vec3& p) { return OpenMesh::dot(n, p - x) >= 0; });
}

// Where point_polygon_form_factor's answer for a triangle is its plain
// contour integral from x, zero, or neither (a limit or a clip is needed).
enum class TriangleView { kZero, kContour, kGeneral };

TriangleView view_of(const Vec3& x, const Vec3& n, const std::array<Vec3, 3>& t) {
  const std::span<const Vec3> polygon(t.data(), 3);
  const PolygonFrame f = frame_of(x, polygon);
  if (f.degenerate) return TriangleView::kZero;
  if (f.singular) return TriangleView::kGeneral;
  if (f.height <= 0.0) return TriangleView::kZero;
  return wholly_above(polygon, x, n) ? TriangleView::kContour : TriangleView::kGeneral;
}

}  // namespace

double point_polygon_form_factor(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon,
                                 const Vec3* approach) {
  if (polygon.size() < 3) return 0.0;
  const PolygonFrame frame = frame_of(x, polygon);
  if (frame.degenerate) return 0.0;
  const Vec3& shooter_normal = frame.normal;
  const double size = frame.size;

  Vec3 eval_point = x;
  if (frame.singular) {
    // Singular configuration: take the limit along the approach direction,
    // projected into x's tangent plane so the path stays on the receiver.
    Vec3 d = approach ? *approach : shooter_normal;
    d -= OpenMesh::dot(d, n) * n;
    const double d_norm = d.norm();
    // Coplanar with the shooter and no in-plane way off it: cosθy = 0 everywhere.
    if (!(d_norm > 1e-12 * std::max(1.0, approach ? approach->norm() : 1.0))) return 0.0;
    eval_point = x + (kApproachStep * size / d_norm) * d;
    // A path that stays in the shooter's plane (x on the shooter's own
    // surface, approached from inside a coplanar face) sees it edge-on:
    // cosθy = 0. Only rounding would put it in front, where the contour
    // integral of an in-plane point is ±1, not 0.
    const double rounding = 8.0 * std::numeric_limits<double>::epsilon() *
                            std::max({eval_point.norm(), polygon[0].norm(), size});
    if (OpenMesh::dot(shooter_normal, eval_point - polygon[0]) <= kPlaneRounding * size + rounding) return 0.0;
  }
  if (OpenMesh::dot(shooter_normal, eval_point - polygon[0]) <= 0.0) return 0.0;  // behind the shooter

  // Wholly above x's tangent plane (the common case) the polygon is its own
  // clip; otherwise clip into a buffer on the stack when it fits (a link's
  // triangle always does), so the hot path allocates nothing.
  if (wholly_above(polygon, eval_point, n)) return std::clamp(contour_integral(eval_point, n, polygon), 0.0, 1.0);
  constexpr std::size_t kStackVertices = 16;
  std::array<Vec3, kStackVertices> stack;
  std::vector<Vec3> heap;
  Vec3* buffer = stack.data();
  if (2 * polygon.size() > kStackVertices) {
    heap.resize(2 * polygon.size());
    buffer = heap.data();
  }
  const std::size_t count = clip_above(polygon, eval_point, n, buffer);
  if (count < 3) return 0.0;
  return std::clamp(contour_integral(eval_point, n, std::span<const Vec3>(buffer, count)), 0.0, 1.0);
}

void shared_edge_form_factors(const Vec3& x, const Vec3& n, std::span<const std::array<Vec3, 3>> triangles,
                              std::span<const std::array<std::int32_t, 3>> corner_edge, const Vec3* approach,
                              std::vector<double>& out, std::span<const std::int32_t> members) {
  // Terms of the edges seen so far in this call, valid where their stamp is
  // this call's: nothing to clear between calls.
  thread_local std::vector<double> term;
  thread_local std::vector<std::uint32_t> stamp;
  thread_local std::uint32_t call = 0;
  if (++call == 0) {
    std::fill(stamp.begin(), stamp.end(), 0U);
    call = 1;
  }
  const std::size_t count = members.empty() ? triangles.size() : members.size();
  out.resize(count);
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t row = members.empty() ? j : static_cast<std::size_t>(members[j]);
    const auto& t = triangles[row];
    const TriangleView view = view_of(x, n, t);
    if (view != TriangleView::kContour) {
      out[j] = view == TriangleView::kZero ? 0.0 : point_triangle_form_factor(x, n, t, approach);
      continue;
    }
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t code = corner_edge[row][k];
      const auto id = static_cast<std::size_t>(code >> 1);
      const bool against = (code & 1) != 0;
      if (id >= term.size()) {
        term.resize(id + 1);
        stamp.resize(id + 1, 0U);
      }
      if (stamp[id] != call) {
        const Vec3& from = t[k];
        const Vec3& to = t[(k + 1) % 3];
        term[id] = against ? edge_term(x, n, to, from) : edge_term(x, n, from, to);
        stamp[id] = call;
      }
      sum += against ? -term[id] : term[id];
    }
    out[j] = std::clamp(-sum / (2.0 * M_PI), 0.0, 1.0);
  }
}

std::optional<double> outline_form_factor(const Vec3& x, const Vec3& n, const Vec3& plane_normal,
                                          std::span<const Vec3> points,
                                          std::span<const std::array<std::int32_t, 2>> outline, bool* clipped) {
  // The region's plane clears x by this much of its size: far above the
  // triangles' own singular tolerance, which is smaller than it for each.
  constexpr double kClearOfPlane = 1e-6;
  if (clipped != nullptr) *clipped = false;
  if (outline.empty()) return std::nullopt;
  const auto point = [&](std::int32_t i) -> const Vec3& { return points[static_cast<std::size_t>(i)]; };
  const Vec3& first = point(outline.front()[0]);
  double size2 = 0.0;
  bool below = false;
  for (const auto& e : outline) {
    below = below || OpenMesh::dot(n, point(e[0]) - x) < 0.0;
    size2 = std::max(size2, (point(e[0]) - first).sqrnorm());
  }
  // Twice the largest distance from `first` bounds the region's diameter.
  if (!(OpenMesh::dot(plane_normal, x - first) > kClearOfPlane * 2.0 * std::sqrt(size2))) return std::nullopt;
  double sum = 0.0;
  if (!below) {
    for (const auto& e : outline) sum += edge_term(x, n, point(e[0]), point(e[1]));
    return std::clamp(-sum / (2.0 * M_PI), 0.0, 1.0);
  }
  // Part of the region lies below x's tangent plane: its contour integral
  // is that of the part above, whose outline is the edges' parts above the
  // plane closed by segments of the line where the two planes meet. Along
  // that line the outline's crossings alternate into and out of the region,
  // so sorted along it they pair up into those segments, each running from
  // where the outline leaves the part above to where it comes back.
  struct Crossing {
    double along;
    Vec3 p;
    bool leaves;
  };
  thread_local std::vector<Crossing> crossings;
  crossings.clear();
  const Vec3 line = OpenMesh::cross(n, plane_normal);
  for (const auto& e : outline) {
    const Vec3 &a = point(e[0]), &b = point(e[1]);
    const double ha = OpenMesh::dot(n, a - x), hb = OpenMesh::dot(n, b - x);
    if (ha >= 0.0 && hb >= 0.0) {
      sum += edge_term(x, n, a, b);
    } else if (ha >= 0.0 || hb >= 0.0) {
      const Vec3 c = a + (ha / (ha - hb)) * (b - a);
      sum += ha >= 0.0 ? edge_term(x, n, a, c) : edge_term(x, n, c, b);
      crossings.push_back({OpenMesh::dot(line, c), c, ha >= 0.0});
    }
  }
  if (crossings.size() % 2 != 0) return std::nullopt;
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& l, const Crossing& r) { return l.along < r.along; });
  for (std::size_t k = 0; k < crossings.size(); k += 2) {
    const Crossing &l = crossings[k], &r = crossings[k + 1];
    // Ties or an outline grazing the line can break the alternation: the
    // caller then takes the triangles one by one.
    if (l.leaves == r.leaves || l.leaves != crossings.front().leaves) return std::nullopt;
    sum += l.leaves ? edge_term(x, n, l.p, r.p) : edge_term(x, n, r.p, l.p);
  }
  if (clipped != nullptr) *clipped = true;
  return std::clamp(-sum / (2.0 * M_PI), 0.0, 1.0);
}

std::optional<double> open_outline_form_factor(const Vec3& x, const Vec3& n,
                                               std::span<const std::array<Vec3, 3>> triangles,
                                               std::span<const Vec3> points,
                                               std::span<const std::array<std::int32_t, 2>> outline) {
  if (outline.empty()) return std::nullopt;
  for (const auto& t : triangles) {
    if (view_of(x, n, t) != TriangleView::kContour) return std::nullopt;
  }
  return outline_contour_form_factor(x, n, points, outline);
}

double outline_contour_form_factor(const Vec3& x, const Vec3& n, std::span<const Vec3> points,
                                   std::span<const std::array<std::int32_t, 2>> outline) {
  double sum = 0.0;
  for (const auto& e : outline) {
    sum += edge_term(x, n, points[static_cast<std::size_t>(e[0])], points[static_cast<std::size_t>(e[1])]);
  }
  return std::clamp(-sum / (2.0 * M_PI), 0.0, 1.0);
}

}  // namespace lhr
