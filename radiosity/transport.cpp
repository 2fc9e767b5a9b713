#include "radiosity/transport.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include "radiosity/form_factor.hpp"
#include "radiosity/sampling.hpp"

namespace lhr {

namespace {

Vec3 unit_normal(const std::array<Vec3, 3>& t) {
  const Vec3 c = OpenMesh::cross(t[1] - t[0], t[2] - t[0]);
  const double len = c.norm();
  return len > 0 ? c / len : Vec3(0, 0, 0);
}

// The point the kernel and shadow rays start from: x itself, nudged toward the
// receiver's interior so that a node on a shooter's plane sees it from the
// side its form factor limit was taken on (docs/design.md §4: finite in corners).
Vec3 kernel_origin(const ReceiverPoint& r, const RayCaster& rays) {
  return r.x + 8.0 * rays.epsilon() * r.approach;
}

// cosθx cosθy / r² (the π cancels in the ratios that use it); 0 for a pair
// that does not face each other.
double kernel(const Vec3& x, const Vec3& nx, const Vec3& y, const Vec3& ny) {
  const Vec3 d = y - x;
  const double r2 = d.sqrnorm();
  if (!(r2 > 0)) return 0.0;
  const double cx = OpenMesh::dot(nx, d), cy = -OpenMesh::dot(ny, d);
  if (cx <= 0 || cy <= 0) return 0.0;
  return cx * cy / (r2 * r2);
}

// A cheap stand-in for the form factor of a triangle of a planar shooter
// (unit normal m) from x: the disc of its area at its centroid,
// A cosθx cosθy / (π r² + A); cosθy is exact at the centroid (x's height over
// the plane is the same for every triangle).
// Triangles within two of their own sizes of x get the exact value: there
// the disc is far off, and for x on the shooter's plane (a wall's foot on
// the floor) the limit puts all of the form factor in the triangles around x.
// Two weights come out. For drawing shadow rays, cosθx is widened by the
// triangle's size so that a triangle across x's horizon is never left out.
// For weighing what the triangles hold (the shape factor) it is not: the
// widening would favour the far triangles over the near exact ones.
struct DiscFormFactors {
  double drawing;
  double weighing;
};

DiscFormFactors disc_form_factors(const Vec3& x, const Vec3& n, const Vec3& m, const ShooterTriangleTable& table,
                                  std::size_t row, const Vec3* approach) {
  const Vec3 d = table.centroid[row] - x;
  const double size2 = table.size2[row];
  const double r2 = d.sqrnorm();
  if (r2 < 4.0 * size2) {
    const double exact = point_triangle_form_factor(x, n, table.corner[row], approach);
    return {exact, exact};
  }
  const double r = std::sqrt(r2), size = std::sqrt(size2);
  const double cos_y = std::clamp(-OpenMesh::dot(m, d) / r, 0.0, 1.0);
  const double area = table.area[row];
  const double disc = area * cos_y / (M_PI * r2 + area);
  return {disc * std::clamp((OpenMesh::dot(n, d) + size) / r, 0.0, 1.0),
          disc * std::clamp(OpenMesh::dot(n, d) / r, 0.0, 1.0)};
}

// Shadow rays of a constant-basis shooter made of triangles. k² rays go to
// triangles drawn systematically by `drawing` (running sums of form factors,
// exact or disc_form_factors), each to a point drawn over its triangle in
// proportion to the kernel cosθx cosθy / r² (near x by solid angle, far by
// area; both kept with chance cosθx or the kernel over a bound of it), so
// that every ray stands for an equal part of its triangle's form factor; a
// ray counts for its triangle's `weighing` share over its drawing share (1
// where the two are the same). Drawing the end points uniformly by area and
// counting the rays alike, as before, measured each triangle's visible share
// of area, not of form factor: the underside of a table inside its aprons,
// lit by a panel low on a wall, read 3 % dark (docs/accuracy.md, "Under the
// table, light source by light source"); weighing such points by the kernel
// lets the few nearest x decide, and with few rays a ratio of weighed sums
// is biased. Pairs that do not face each other send no ray.
struct RayOutcome {
  std::size_t triangle;
  bool clear;
  double weight;
};

// Triangle j's term of running sums.
double share(const std::vector<double>& cumulative, std::size_t j) {
  return cumulative[j] - (j > 0 ? cumulative[j - 1] : 0.0);
}

// An upper bound of cosθx = n·ω over the directions ω of a triangle seen
// from x (unit corner directions a, b, c): the triangle lies in the cap about
// its corners' mean direction that reaches its farthest corner.
double cosine_bound(const Vec3& n, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 sum = a + b + c;
  const double len = sum.norm();
  if (!(len > 0)) return 1.0;
  const Vec3 g = sum / len;
  const double cos_radius = std::min({OpenMesh::dot(g, a), OpenMesh::dot(g, b), OpenMesh::dot(g, c)});
  if (!(cos_radius > 0.0)) return 1.0;  // a cap of 90° or more
  const double cos_centre = OpenMesh::dot(n, g);
  if (cos_centre >= cos_radius) return 1.0;  // n points into the cap
  const double sin_radius = std::sqrt(std::max(0.0, 1.0 - cos_radius * cos_radius));
  const double sin_centre = std::sqrt(std::max(0.0, 1.0 - cos_centre * cos_centre));
  return std::min(1.0, cos_centre * cos_radius + sin_centre * sin_radius);
}

// Draws within one triangle before a ray is given up: only a triangle that
// barely rises above x's horizon accepts less than one in this many, and
// its form factor is then too small to matter.
constexpr int kCosineDraws = 32;

// Beyond this many of its longest edges from x, a triangle's kernel is
// bounded well enough over it that a point drawn by area and kept with
// chance the kernel over a bound of it (kernel_drawn_point) takes a few
// cheap attempts: it is drawn as Arvo's construction draws it, at a small
// part of the cost (drawing every ray by solid angle made a Cornell box
// solve half again as long; drawing by area beyond four edges, 19 % longer).
constexpr double kFarTriangle = 2.0;

// A point of a triangle far from x (beyond kFarTriangle of its sizes), drawn
// in proportion to the kernel cosθx cosθy / r² over its area: uniformly,
// kept with chance the kernel over a bound of it (cosθx r is linear over the
// triangle and greatest at a corner, cosθy r is x's height over its plane,
// and r is at least that height and the centroid's distance less the
// farthest corner's from it). nullopt where x faces no part of it.
std::optional<Vec3> kernel_drawn_point(const Vec3& origin, const Vec3& n, const std::array<Vec3, 3>& corners,
                                       const Vec3& centroid, const Vec3& ny, double height, std::uint64_t key) {
  double along_n = 0.0, spread2 = 0.0;
  for (const Vec3& c : corners) {
    along_n = std::max(along_n, OpenMesh::dot(n, c - origin));
    spread2 = std::max(spread2, (c - centroid).sqrnorm());
  }
  const double nearest = std::max((centroid - origin).norm() - std::sqrt(spread2), height);
  if (!(along_n > 0.0) || !(nearest > 0.0)) return std::nullopt;
  const double r2 = nearest * nearest;
  const double bound = along_n * height / (r2 * r2);
  // Three 21-bit uniforms from one hash an attempt: the attempts are most of
  // this draw's cost.
  constexpr double kUnit21 = 0x1.0p-21;
  for (int attempt = 0; attempt < kCosineDraws; ++attempt) {
    const std::uint64_t bits = mix_bits(key + static_cast<std::uint64_t>(attempt) * 0x9E3779B97F4A7C15ull);
    double s = static_cast<double>(bits & 0x1FFFFF) * kUnit21;
    double t = static_cast<double>((bits >> 21) & 0x1FFFFF) * kUnit21;
    if (s + t > 1.0) {  // fold the unit square onto the triangle: uniform by area
      s = 1.0 - s;
      t = 1.0 - t;
    }
    const Vec3 y = (1.0 - s - t) * corners[0] + s * corners[1] + t * corners[2];
    if (static_cast<double>(bits >> 42) * kUnit21 * 0.5 * bound < kernel(origin, n, y, ny)) return y;
  }
  const Vec3 y = at(corners, uniform_triangle_sample(key));
  if (!(kernel(origin, n, y, ny) > 0.0)) return std::nullopt;
  return y;
}

// A point of triangle `corners` (unit normal ny, x in front of it at
// `height` over its plane) whose direction from `origin` is drawn in
// proportion to cosθx over the triangle's solid angle (uniformly by solid
// angle, kept with chance cosθx over a bound of it). Where no draw is kept
// the triangle barely rises above x's horizon; a point drawn by area that
// x faces stands in, so that a link hidden by its shooter's every triangle
// still has a ray that says so. nullopt where x faces no such point.
// `triangle` is the spherical triangle the corners make seen from origin, and
// `bound` its cosine_bound (0 where it is not valid): set up once for all the
// rays a triangle gets.
std::optional<Vec3> cosine_drawn_point(const Vec3& origin, const Vec3& n, const std::array<Vec3, 3>& corners,
                                       const SphericalTriangle& triangle, double bound, const Vec3& ny,
                                       double height, std::uint64_t key) {
  for (int attempt = 0; attempt < kCosineDraws && bound > 0.0; ++attempt) {
    const std::uint64_t k = sample_key(key, static_cast<std::uint64_t>(attempt));
    const std::optional<Vec3> direction =
        triangle.sample(unit_double(sample_key(k, 1)), unit_double(sample_key(k, 2)));
    if (!direction) break;
    const double cos_x = OpenMesh::dot(n, *direction), cos_y = -OpenMesh::dot(ny, *direction);
    if (!(cos_y > 0.0) || !(cos_x > 0.0)) continue;
    if (unit_double(sample_key(k, 3)) * bound < cos_x) return origin + (height / cos_y) * *direction;
  }
  const Vec3 y = at(corners, uniform_triangle_sample(key));
  if (!(kernel(origin, n, y, ny) > 0.0)) return std::nullopt;
  return y;
}

void trace_shadow_rays(const ReceiverPoint& receiver, const ShooterTriangles& triangles,
                       const std::vector<double>& drawing, const std::vector<double>& weighing,
                       const RayCaster& rays, const TransportSampling& sampling, std::uint64_t& ray_count,
                       std::vector<RayOutcome>& outcomes) {
  outcomes.clear();
  const Vec3 origin = kernel_origin(receiver, rays);
  const std::size_t count = static_cast<std::size_t>(std::max(1, sampling.k * sampling.k));
  const double offset = unit_double(sample_key(sampling.key, 1));
  // One set per thread, reused: a link's coefficients are computed millions
  // of times in a solve, and the allocations showed in its profile.
  thread_local std::vector<ShadowRay> segments;
  thread_local std::vector<std::uint8_t> blocked;
  segments.clear();
  const ShooterTriangleTable& table = *triangles.table;
  // Drawn systematically, a near triangle's rays come one after another: its
  // spherical triangle and cosine bound are set up once for all of them.
  std::size_t near_row = std::numeric_limits<std::size_t>::max();
  std::optional<SphericalTriangle> near;
  double near_bound = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double u = (static_cast<double>(i) + offset) / static_cast<double>(count) * drawing.back();
    const std::size_t j = std::min<std::size_t>(
        static_cast<std::size_t>(std::lower_bound(drawing.begin(), drawing.end(), u) - drawing.begin()),
        triangles.size() - 1);
    const double drawn = share(drawing, j);
    if (!(drawn > 0.0)) continue;
    const std::size_t row = triangles.row(j);
    const Vec3& ny = table.normal[row];
    // x behind the triangle's plane sees its back: no transport.
    const double height = OpenMesh::dot(ny, origin - table.corner[row][0]);
    if (!(height > 0.0)) continue;
    const std::uint64_t key = sample_key(sampling.key, 2, i);
    const bool far = (table.centroid[row] - origin).sqrnorm() > kFarTriangle * kFarTriangle * table.size2[row];
    if (!far && row != near_row) {
      near.emplace(origin, table.corner[row]);
      near_bound = near->valid() ? cosine_bound(receiver.normal, near->a(), near->b(), near->c()) : 0.0;
      near_row = row;
    }
    const std::optional<Vec3> y =
        far ? kernel_drawn_point(origin, receiver.normal, table.corner[row], table.centroid[row], ny, height, key)
            : cosine_drawn_point(origin, receiver.normal, table.corner[row], *near, near_bound, ny, height, key);
    if (!y) continue;
    segments.push_back({rays.lift(origin, receiver.normal), rays.lift(*y, ny)});
    outcomes.push_back({j, true, &weighing == &drawing ? 1.0 : share(weighing, j) / drawn});
  }
  if (segments.empty()) return;
  blocked.assign(segments.size(), 0);
  rays.occluded(segments, blocked);
  ray_count += segments.size();
  for (std::size_t i = 0; i < segments.size(); ++i) outcomes[i].clear = blocked[i] == 0;
}

// f[0] of a constant-basis shooter of exact unoccluded form factor `ff`:
// ff times the weighted share c of its shadow rays that arrive (1 when none
// was sent: nothing says it is hidden). With a shape, what each part holds
// weighs it, Σ_j F_j V_j value_j / carried, as ff c times the mean of what
// is seen: the exact mean M of the triangles' values as their form factors
// (`weighing`) weigh them, moved by the hidden share h = 1 − c times how far
// the arriving rays' mean lies from the blocked ones' (M = c m_clear +
// h m_blocked in expectation). A shooter seen whole keeps M and no
// sampling noise, a hidden one gives 0, and the part of a floor under a
// table, both dark and hidden from the ceiling, is left out of what reaches
// it (docs/accuracy.md, "What a table hides"). The mean of the visible part
// taken as a ratio of two differences, as before, had to be clamped where
// nearly all is hidden, and with rays of unequal weight read up to 4 % low
// there (docs/accuracy.md, "Under the table, light source by light source").
double occluded_transport(double ff, const std::vector<double>& weighing, const ShooterShape* shape,
                          const std::vector<RayOutcome>& rays, const ShooterTriangles& triangles) {
  double weights = 0.0;
  for (const RayOutcome& r : rays) weights += r.weight;
  // Rays sent only to triangles that weigh nothing (drawn by the widened
  // estimates, all below x's horizon) still say what is hidden: count them
  // alike.
  const bool alike = !(weights > 0.0);
  double clear = 0.0, hidden = 0.0, clear_value = 0.0, hidden_value = 0.0;
  for (const RayOutcome& r : rays) {
    const double w = alike ? 1.0 : r.weight;
    const double value = shape != nullptr ? shape->value[triangles.row(r.triangle)] : 0.0;
    (r.clear ? clear : hidden) += w;
    (r.clear ? clear_value : hidden_value) += w * value;
  }
  const double seen = rays.empty() ? 1.0 : clear / (clear + hidden);
  // Without a shape, or with nothing weighed to say how the values spread,
  // the visible share alone.
  if (shape == nullptr || !(shape->carried > 0.0) || !(weighing.back() > 0.0)) return ff * seen;
  if (!(seen > 0.0)) return 0.0;
  assert(shape->value.size() == triangles.table->size());
  assert(weighing.size() == triangles.size());
  double weighted = 0.0;
  for (std::size_t j = 0; j < weighing.size(); ++j) weighted += share(weighing, j) * shape->value[triangles.row(j)];
  double mean = weighted / weighing.back();
  if (hidden > 0.0) mean += (1.0 - seen) * (clear_value / clear - hidden_value / hidden);
  return ff * seen * std::max(0.0, mean) / shape->carried;
}

// How far from a shooter triangle (in its longest edges, from its centroid)
// the kernel is smooth enough over it for sampled weights to split its form
// factor among the corners; nearer, the split is integrated.
constexpr double kNearShooter = 3.0;
// Depth of the subdivision that integrates the split: pieces next to x end
// 2^-6 of the triangle across, where the hat functions vary by 1/64.
constexpr int kSplitDepth = 6;

double longest_edge(const std::array<Vec3, 3>& t) {
  return std::sqrt(std::max({(t[1] - t[0]).sqrnorm(), (t[2] - t[1]).sqrnorm(), (t[0] - t[2]).sqrnorm()}));
}

// F^l = ∫ N^l cosθx cosθy / (π r²) dA without occlusion, for a receiver
// near the triangle: the triangle is split into pieces, finer toward x, and
// each piece's exact form factor goes to the corners by the hat values at
// its centroid. Weighting sample points by the kernel instead lets the few
// samples nearest x decide the split, while the exact integral is ruled by
// the region next to x: in a corner, the far (brighter) corners got too
// much weight and ceiling vertices along a wall read 10–20 % bright.
std::array<double, 3> near_basis_form_factors(const ReceiverPoint& receiver, const std::array<Vec3, 3>& shooter,
                                              const Vec3* approach) {
  struct Piece {
    std::array<Vec3, 3> corner;
    std::array<Vec3, 3> hat;  // the corners' barycentric coordinates in the shooter
    int depth;
  };
  std::array<double, 3> out{0.0, 0.0, 0.0};
  // Reused across calls (see TriangleTransportScratch).
  thread_local std::vector<Piece> stack;
  stack.assign(1, {shooter, {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}, 0});
  while (!stack.empty()) {
    const Piece p = stack.back();
    stack.pop_back();
    const Vec3 centre = (p.corner[0] + p.corner[1] + p.corner[2]) / 3.0;
    if (p.depth < kSplitDepth && (receiver.x - centre).norm() < kNearShooter * longest_edge(p.corner)) {
      std::array<Vec3, 3> mid, mid_hat;
      for (int k = 0; k < 3; ++k) {
        mid[k] = 0.5 * (p.corner[k] + p.corner[(k + 1) % 3]);
        mid_hat[k] = 0.5 * (p.hat[k] + p.hat[(k + 1) % 3]);
      }
      for (int k = 0; k < 3; ++k) {
        stack.push_back({{p.corner[k], mid[k], mid[(k + 2) % 3]}, {p.hat[k], mid_hat[k], mid_hat[(k + 2) % 3]},
                         p.depth + 1});
      }
      stack.push_back({mid, mid_hat, p.depth + 1});
      continue;
    }
    const double f = point_triangle_form_factor(receiver.x, receiver.normal, p.corner, approach);
    if (!(f > 0.0)) continue;
    const Vec3 hat = (p.hat[0] + p.hat[1] + p.hat[2]) / 3.0;
    for (int l = 0; l < 3; ++l) out[l] += f * hat[l];
  }
  return out;
}

// SharedLinkGeometry's memo: per receiver point and call site, what a draw
// of the scope's link worked out before its rays.
enum class GeometrySite : std::uint8_t { kTriangle, kCluster, kSurface, kPlanarDiscs, kCurvedDiscs };

struct SharedGeometry {
  GeometrySite site;
  Vec3 x, normal, approach;
  double ff = 0.0;
  bool near = false;  // triangle: x is near enough for the integrated split
  bool has_split = false;
  std::array<double, 3> split{0.0, 0.0, 0.0};
  bool seen_plainly = true;  // curved cluster: every root seen plainly
  std::vector<double> first, second;
};

struct SharedGeometryMemo {
  int open_scopes = 0;
  // The innermost scope's entries are [base, used); the outer scopes' lie
  // below base, unseen by it; the rest keep their capacity.
  std::size_t base = 0;
  std::size_t used = 0;
  std::vector<SharedGeometry> entries;
};

thread_local SharedGeometryMemo t_shared_geometry;

bool same_point(const SharedGeometry& g, const ReceiverPoint& r) {
  return g.x == r.x && g.normal == r.normal && g.approach == r.approach;
}

// The entry this scope made for (site, receiver), or null.
SharedGeometry* shared_geometry(GeometrySite site, const ReceiverPoint& receiver) {
  SharedGeometryMemo& memo = t_shared_geometry;
  if (memo.open_scopes == 0) return nullptr;
  for (std::size_t i = memo.base; i < memo.used; ++i) {
    if (memo.entries[i].site == site && same_point(memo.entries[i], receiver)) return &memo.entries[i];
  }
  return nullptr;
}

// A new entry for (site, receiver) in this scope, or null without a scope.
SharedGeometry* new_shared_geometry(GeometrySite site, const ReceiverPoint& receiver) {
  SharedGeometryMemo& memo = t_shared_geometry;
  if (memo.open_scopes == 0) return nullptr;
  if (memo.used == memo.entries.size()) memo.entries.emplace_back();
  SharedGeometry& g = memo.entries[memo.used++];
  g.site = site;
  g.x = receiver.x;
  g.normal = receiver.normal;
  g.approach = receiver.approach;
  g.ff = 0.0;
  g.near = g.has_split = false;
  g.seen_plainly = true;
  g.first.clear();
  g.second.clear();
  return &g;
}

// triangle_transport's working arrays, one set per thread and reused: it
// runs once per link, and allocating them on every call cost a few per cent
// of a solve, and a tenth of it under AddressSanitizer.
struct TriangleTransportScratch {
  std::vector<TriangleSample> samples;
  std::vector<double> weight;
  std::vector<ShadowRay> segments;
  std::vector<std::size_t> traced;
  std::vector<std::uint8_t> blocked;
};

}  // namespace

SharedLinkGeometry::SharedLinkGeometry() : outer_base_(t_shared_geometry.base) {
  // A scope opened inside another (a task run while one waits) sees none of
  // the outer one's entries, which may be for the same point and another
  // shooter, and leaves them as they were.
  SharedGeometryMemo& memo = t_shared_geometry;
  ++memo.open_scopes;
  memo.base = memo.used;
}

SharedLinkGeometry::~SharedLinkGeometry() {
  SharedGeometryMemo& memo = t_shared_geometry;
  --memo.open_scopes;
  memo.used = memo.base;
  memo.base = outer_base_;
}

TransportCoefficients merge_child_coefficients(const std::array<TransportCoefficients, 4>& children) {
  // Parent corner L's hat function at corner l of child c: 1 at the parent's
  // own corner, ½ at an edge midpoint (child 3's corner k is the midpoint
  // opposite the parent's corner k).
  constexpr double kHat[4][3][3] = {
      {{1, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}},
      {{0.5, 0.5, 0}, {0, 1, 0}, {0, 0.5, 0.5}},
      {{0.5, 0, 0.5}, {0, 0.5, 0.5}, {0, 0, 1}},
      {{0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}},
  };
  std::array<double, 3> f{0.0, 0.0, 0.0};
  double unoccluded = 0.0;
  for (int c = 0; c < 4; ++c) {
    for (int l = 0; l < 3; ++l) {
      for (int corner = 0; corner < 3; ++corner) f[corner] += kHat[c][l][corner] * children[c].f[l];
    }
    unoccluded += children[c].unoccluded;
  }
  TransportCoefficients out;
  for (int l = 0; l < 3; ++l) out.f[l] = static_cast<float>(f[l]);
  out.unoccluded = static_cast<float>(unoccluded);
  return out;
}

TransportCoefficients triangle_transport(const ReceiverPoint& receiver, const std::array<Vec3, 3>& shooter,
                                         const RayCaster& rays, const TransportSampling& sampling,
                                         std::uint64_t& ray_count) {
  TransportCoefficients out;
  const Vec3* approach = receiver.approach.sqrnorm() > 0 ? &receiver.approach : nullptr;
  SharedGeometry* shared = shared_geometry(GeometrySite::kTriangle, receiver);
  if (shared == nullptr) {
    const double exact = point_triangle_form_factor(receiver.x, receiver.normal, shooter, approach);
    const bool near =
        (receiver.x - (shooter[0] + shooter[1] + shooter[2]) / 3.0).norm() < kNearShooter * longest_edge(shooter);
    shared = new_shared_geometry(GeometrySite::kTriangle, receiver);
    thread_local SharedGeometry unshared;
    if (shared == nullptr) shared = &unshared;
    shared->ff = exact;
    shared->near = near;
    shared->has_split = false;
  }
  const double ff = shared->ff;
  if (!(ff > 0.0)) return out;
  out.unoccluded = static_cast<float>(ff);

  const Vec3 ny = unit_normal(shooter);
  const Vec3 origin = kernel_origin(receiver, rays);
  thread_local TriangleTransportScratch scratch;
  auto& [samples, weight, segments, traced, blocked] = scratch;
  stratified_triangle_samples(std::max(1, sampling.k), sampling.key, samples);
  weight.resize(samples.size());
  segments.clear();
  traced.clear();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vec3 y = at(shooter, samples[i]);
    weight[i] = kernel(origin, receiver.normal, y, ny);
    if (weight[i] > 0) {
      segments.push_back({rays.lift(origin, receiver.normal), rays.lift(y, ny)});
      traced.push_back(i);
    }
  }
  if (segments.empty()) {
    // The samples all miss the part above x's horizon (a sliver of the
    // triangle): nothing says it is hidden, and its basis split is unknown.
    out.f.fill(static_cast<float>(ff / 3.0));
    return out;
  }
  blocked.assign(segments.size(), 0);
  rays.occluded(segments, blocked);
  ray_count += segments.size();
  double total = 0.0;
  std::array<double, 3> visible{0.0, 0.0, 0.0}, seen{0.0, 0.0, 0.0};
  for (std::size_t t = 0; t < traced.size(); ++t) {
    const std::size_t i = traced[t];
    total += weight[i];
    for (int l = 0; l < 3; ++l) seen[l] += samples[i].barycentric[l] * weight[i];
    if (blocked[t]) continue;
    for (int l = 0; l < 3; ++l) visible[l] += samples[i].barycentric[l] * weight[i];
  }
  if (shared->near) {
    // The split integrated; the samples only say how much of each corner's
    // share is hidden.
    if (!shared->has_split) {
      shared->split = near_basis_form_factors(receiver, shooter, approach);
      shared->has_split = true;
    }
    const std::array<double, 3>& split = shared->split;
    const double sum = split[0] + split[1] + split[2];
    for (int l = 0; l < 3; ++l) {
      const double share = sum > 0 ? ff * split[l] / sum : ff / 3.0;
      const double open = seen[l] > 0 ? visible[l] / seen[l] : (total > 0 ? (visible[0] + visible[1] + visible[2]) / total : 1.0);
      out.f[l] = static_cast<float>(share * open);
    }
    return out;
  }
  for (int l = 0; l < 3; ++l) out.f[l] = static_cast<float>(ff * visible[l] / total);
  return out;
}

ShooterTriangleTable::ShooterTriangleTable(std::span<const std::array<Vec3, 3>> triangles)
    : corner(triangles.begin(), triangles.end()) {
  normal.reserve(corner.size());
  centroid.reserve(corner.size());
  area.reserve(corner.size());
  size2.reserve(corner.size());
  for (const auto& t : corner) {
    normal.push_back(unit_normal(t));
    centroid.push_back((t[0] + t[1] + t[2]) / 3.0);
    area.push_back(0.5 * OpenMesh::cross(t[1] - t[0], t[2] - t[0]).norm());
    size2.push_back(std::max({(t[1] - t[0]).sqrnorm(), (t[2] - t[1]).sqrnorm(), (t[0] - t[2]).sqrnorm()}));
  }
}

std::size_t ShooterTriangleTable::bytes() const {
  return corner.capacity() * sizeof(corner[0]) + (normal.capacity() + centroid.capacity()) * sizeof(Vec3) +
         (area.capacity() + size2.capacity()) * sizeof(double);
}

TransportCoefficients cluster_transport(const ReceiverPoint& receiver, const ShooterTriangles& shooter,
                                        const RayCaster& rays, const TransportSampling& sampling,
                                        std::uint64_t& ray_count, const ShooterShape* shape,
                                        std::span<const std::array<std::int32_t, 3>> corner_edges) {
  TransportCoefficients out;
  const Vec3* approach = receiver.approach.sqrnorm() > 0 ? &receiver.approach : nullptr;
  thread_local std::vector<double> cumulative;
  double ff = 0.0;
  if (const SharedGeometry* shared = shared_geometry(GeometrySite::kCluster, receiver)) {
    cumulative = shared->first;
    ff = shared->ff;
  } else {
    cumulative.clear();
    const ShooterTriangleTable& table = *shooter.table;
    if (!corner_edges.empty()) {
      assert(corner_edges.size() == table.size());
      shared_edge_form_factors(receiver.x, receiver.normal, table.corner, corner_edges, approach, cumulative,
                               shooter.members);
    } else {
      cumulative.resize(shooter.size());
      for (std::size_t j = 0; j < shooter.size(); ++j) {
        cumulative[j] =
            point_triangle_form_factor(receiver.x, receiver.normal, table.corner[shooter.row(j)], approach);
      }
    }
    for (double& f : cumulative) {
      ff += f;
      f = ff;
    }
    if (SharedGeometry* made = new_shared_geometry(GeometrySite::kCluster, receiver)) {
      made->first = cumulative;
      made->ff = ff;
    }
  }
  if (!(ff > 0.0) || shooter.size() == 0) return out;
  out.unoccluded = static_cast<float>(ff);
  // Shadow rays go to triangles drawn in proportion to their share of the
  // form factor (systematic sampling), so hidden or back-facing parts of a
  // large shooter do not dilute the parts that carry the energy.
  // Which rays arrived matters only to the shape factor.
  thread_local std::vector<RayOutcome> outcomes;
  trace_shadow_rays(receiver, shooter, cumulative, cumulative, rays, sampling, ray_count, outcomes);
  out.f[0] = static_cast<float>(occluded_transport(ff, cumulative, shape, outcomes, shooter));
  return out;
}

TransportCoefficients cluster_transport(const ReceiverPoint& receiver,
                                        std::span<const std::array<Vec3, 3>> shooter, const RayCaster& rays,
                                        const TransportSampling& sampling, std::uint64_t& ray_count,
                                        const ShooterShape* shape) {
  const ShooterTriangleTable table(shooter);
  return cluster_transport(receiver, ShooterTriangles{&table, {}}, rays, sampling, ray_count, shape);
}

TransportCoefficients surface_transport(const ReceiverPoint& receiver, std::span<const std::vector<Vec3>> polygons,
                                        const ShooterTriangles& triangles, const RayCaster& rays,
                                        const TransportSampling& sampling, std::uint64_t& ray_count,
                                        const ShooterShape* shape) {
  const Vec3* approach = receiver.approach.sqrnorm() > 0 ? &receiver.approach : nullptr;
  double ff = 0.0;
  if (const SharedGeometry* shared = shared_geometry(GeometrySite::kSurface, receiver)) {
    ff = shared->ff;
  } else {
    for (const auto& polygon : polygons) ff += point_polygon_form_factor(receiver.x, receiver.normal, polygon, approach);
    if (SharedGeometry* made = new_shared_geometry(GeometrySite::kSurface, receiver)) made->ff = ff;
  }
  return planar_shooter_transport(receiver, ff, triangles, rays, sampling, ray_count, shape, ShooterHorizon::kUnknown);
}

TransportCoefficients surface_transport(const ReceiverPoint& receiver, std::span<const std::vector<Vec3>> polygons,
                                        std::span<const std::array<Vec3, 3>> triangles, const RayCaster& rays,
                                        const TransportSampling& sampling, std::uint64_t& ray_count,
                                        const ShooterShape* shape) {
  const ShooterTriangleTable table(triangles);
  return surface_transport(receiver, polygons, ShooterTriangles{&table, {}}, rays, sampling, ray_count, shape);
}

namespace {

// The running sums by which disc_drawn_transport draws its shadow rays
// (`drawing`) and weighs what they find (`weighing`), one entry per
// triangle; one set per thread, reused, as for triangle_transport.
struct DiscWeights {
  std::vector<double> drawing;
  std::vector<double> weighing;
};

// Which normal a shooter triangle's disc estimate takes: the plane's, shared
// by every triangle of a planar shooter, or each triangle's own where the
// shooter bends. With their own normals the triangles must also be seen
// plainly (open_outline_form_factor's condition: x in front of the
// triangle's plane, clear of it, and the triangle wholly above x's tangent
// plane); fill_disc_weights returns false as soon as one is not.
enum class TriangleNormals { kShared, kOwnSeenPlainly };

// Form factors of the triangles approximated away from x: the exact one for
// every triangle of a large surface cost half again the solve time of a
// furnished room.
bool fill_disc_weights(const ReceiverPoint& receiver, const ShooterTriangles& triangles, ShooterHorizon horizon,
                       TriangleNormals normals, DiscWeights& out) {
  const Vec3* approach = receiver.approach.sqrnorm() > 0 ? &receiver.approach : nullptr;
  out.drawing.clear();
  out.weighing.clear();
  const ShooterTriangleTable& table = *triangles.table;
  const Vec3 m = table.normal[triangles.row(0)];
  double sum = 0.0, weighed = 0.0;
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    const std::size_t row = triangles.row(j);
    if (normals == TriangleNormals::kOwnSeenPlainly) {
      const auto& t = table.corner[row];
      // The same tolerance as the form factor's own (a billionth of the
      // size), against the longest edge, which is never shorter.
      if (!(OpenMesh::dot(table.normal[row], receiver.x - t[0]) > 1e-9 * std::sqrt(table.size2[row]))) return false;
      for (const Vec3& corner : t) {
        if (!(OpenMesh::dot(receiver.normal, corner - receiver.x) >= 0.0)) return false;
      }
    }
    DiscFormFactors f = disc_form_factors(receiver.x, receiver.normal,
                                          normals == TriangleNormals::kShared ? m : table.normal[row], table, row,
                                          approach);
    if (horizon == ShooterHorizon::kCrossing) {
      const auto& t = table.corner[row];
      int above = 0;
      for (const Vec3& corner : t) above += OpenMesh::dot(receiver.normal, corner - receiver.x) >= 0.0 ? 1 : 0;
      if (above == 0) f = {0.0, 0.0};
      if (above == 1 || above == 2) f.weighing = point_triangle_form_factor(receiver.x, receiver.normal, t, approach);
      f.drawing = f.weighing;
    }
    sum += horizon == ShooterHorizon::kUnknown ? f.drawing : f.weighing;
    out.drawing.push_back(sum);
    weighed += f.weighing;
    out.weighing.push_back(weighed);
  }
  return true;
}

// fill_disc_weights, once per receiver point in a SharedLinkGeometry scope.
// The planar and the curved call site differ in horizon and normals, and
// each keeps its own entries.
bool fill_shared_disc_weights(const ReceiverPoint& receiver, const ShooterTriangles& triangles,
                              ShooterHorizon horizon, TriangleNormals normals, DiscWeights& out) {
  const GeometrySite site =
      normals == TriangleNormals::kShared ? GeometrySite::kPlanarDiscs : GeometrySite::kCurvedDiscs;
  if (const SharedGeometry* shared = shared_geometry(site, receiver)) {
    out.drawing = shared->first;
    out.weighing = shared->second;
    return shared->seen_plainly;
  }
  const bool seen_plainly = fill_disc_weights(receiver, triangles, horizon, normals, out);
  if (SharedGeometry* made = new_shared_geometry(site, receiver)) {
    made->first = out.drawing;
    made->second = out.weighing;
    made->seen_plainly = seen_plainly;
  }
  return seen_plainly;
}

// A constant-basis shooter whose exact unoccluded form factor `ff` is known,
// its shadow rays drawn by `weights`.
TransportCoefficients disc_drawn_transport(const ReceiverPoint& receiver, double ff,
                                           const ShooterTriangles& triangles, const DiscWeights& weights,
                                           const RayCaster& rays, const TransportSampling& sampling,
                                           std::uint64_t& ray_count, const ShooterShape* shape) {
  TransportCoefficients out;
  out.unoccluded = static_cast<float>(ff);
  // Nothing drawn: nothing says the surface is hidden.
  if (!(weights.drawing.back() > 0.0)) {
    out.f[0] = static_cast<float>(ff);
    return out;
  }
  // Each ray stands for its triangle's own form factor over the chance of
  // drawing it, so the widened drawing weights, which favour far triangles,
  // do not let them decide how much is seen: just above a table the far
  // floor is the part in view, and counting rays alike read 16 % high
  // (docs/accuracy.md, "What a table hides").
  thread_local std::vector<RayOutcome> outcomes;
  trace_shadow_rays(receiver, triangles, weights.drawing, weights.weighing, rays, sampling, ray_count, outcomes);
  out.f[0] = static_cast<float>(occluded_transport(ff, weights.weighing, shape, outcomes, triangles));
  return out;
}

}  // namespace

void drawing_form_factor_sums(const Vec3& x, const Vec3& n, const ShooterTriangles& triangles,
                              std::vector<double>& sums) {
  sums.clear();
  if (triangles.size() == 0) return;
  const ShooterTriangleTable& table = *triangles.table;
  const Vec3 m = table.normal[triangles.row(0)];
  double sum = 0.0;
  for (std::size_t j = 0; j < triangles.size(); ++j) {
    sum += disc_form_factors(x, n, m, table, triangles.row(j), nullptr).weighing;
    sums.push_back(sum);
  }
}

TransportCoefficients planar_shooter_transport(const ReceiverPoint& receiver, double ff,
                                               const ShooterTriangles& triangles, const RayCaster& rays,
                                               const TransportSampling& sampling, std::uint64_t& ray_count,
                                               const ShooterShape* shape, ShooterHorizon horizon) {
  if (!(ff > 0.0) || triangles.size() == 0) return {};
  thread_local DiscWeights weights;
  fill_shared_disc_weights(receiver, triangles, horizon, TriangleNormals::kShared, weights);
  return disc_drawn_transport(receiver, ff, triangles, weights, rays, sampling, ray_count, shape);
}

std::optional<TransportCoefficients> curved_cluster_transport(
    const ReceiverPoint& receiver, const ShooterTriangles& triangles, std::span<const Vec3> points,
    std::span<const std::array<std::int32_t, 2>> outline, const RayCaster& rays, const TransportSampling& sampling,
    std::uint64_t& ray_count, const ShooterShape* shape) {
  if (outline.empty() || triangles.size() == 0) return std::nullopt;
  thread_local DiscWeights weights;
  if (!fill_shared_disc_weights(receiver, triangles, ShooterHorizon::kAbove, TriangleNormals::kOwnSeenPlainly,
                                weights)) {
    return std::nullopt;
  }
  const double ff = outline_contour_form_factor(receiver.x, receiver.normal, points, outline);
  if (!(ff > 0.0)) return TransportCoefficients{};
  return disc_drawn_transport(receiver, ff, triangles, weights, rays, sampling, ray_count, shape);
}

}  // namespace lhr
