// Transport coefficients of whole-surface shooters against an independent
// truth: cosine-weighted rays traced analytically, without Embree.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "radiosity/form_factor.hpp"
#include "radiosity/ray_caster.hpp"
#include "radiosity/root_clusters.hpp"
#include "radiosity/sampling.hpp"
#include "radiosity/transport.hpp"

namespace lhr {
namespace {

constexpr double kRoom = 4.0;                   // floor [0, 4]² in y = 0, facing +y
const Vec3 kBoxLow(1.5, 0, 1.5), kBoxHigh(2.5, 1, 2.5);  // a block standing on it

// The floor as the solver's roots would be: an n × n grid of squares, two
// triangles each, counter-clockwise seen from above.
std::vector<std::array<Vec3, 3>> floor_triangles(int n) {
  std::vector<std::array<Vec3, 3>> out;
  const double s = kRoom / n;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Vec3 a(i * s, 0, j * s), b(i * s, 0, (j + 1) * s), c((i + 1) * s, 0, (j + 1) * s),
          d((i + 1) * s, 0, j * s);
      out.push_back({a, b, c});
      out.push_back({a, c, d});
    }
  }
  return out;
}

// The block's four sides and top, facing out (its bottom rests on the floor).
TriMesh block() {
  TriMesh m;
  const auto v = [&](double x, double y, double z) { return m.add_vertex(Vec3(x, y, z)); };
  const double x0 = kBoxLow[0], x1 = kBoxHigh[0], z0 = kBoxLow[2], z1 = kBoxHigh[2], h = kBoxHigh[1];
  const auto quad = [&](TriMesh::VertexHandle a, TriMesh::VertexHandle b, TriMesh::VertexHandle c,
                        TriMesh::VertexHandle d) {
    m.add_face(a, b, c);
    m.add_face(a, c, d);
  };
  quad(v(x0, h, z0), v(x0, h, z1), v(x1, h, z1), v(x1, h, z0));  // top, +y
  quad(v(x0, 0, z0), v(x0, h, z0), v(x1, h, z0), v(x1, 0, z0));  // −z
  quad(v(x0, 0, z1), v(x1, 0, z1), v(x1, h, z1), v(x0, h, z1));  // +z
  quad(v(x0, 0, z0), v(x0, 0, z1), v(x0, h, z1), v(x0, h, z0));  // −x
  quad(v(x1, 0, z0), v(x1, h, z0), v(x1, h, z1), v(x1, 0, z1));  // +x
  return m;
}

// Distance along d to the block, if the ray from o meets it.
std::optional<double> hit_block(const Vec3& o, const Vec3& d) {
  double t0 = 0.0, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-300) {
      if (o[a] < kBoxLow[a] || o[a] > kBoxHigh[a]) return std::nullopt;
      continue;
    }
    double ta = (kBoxLow[a] - o[a]) / d[a], tb = (kBoxHigh[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return std::nullopt;
  }
  return t0;
}

// Form factor from x (unit normal n) to the part of the floor it sees past
// the block: the share of cosine-distributed directions that reach the floor first.
double visible_floor_form_factor(const Vec3& x, const Vec3& n, int rays) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 t = OpenMesh::cross(n, helper).normalized(), b = OpenMesh::cross(n, t);
  int floor_hits = 0;
  for (int i = 0; i < rays; ++i) {
    const double u1 = uniform(rng), u2 = uniform(rng);
    const double r = std::sqrt(u1), phi = 2.0 * M_PI * u2;
    const Vec3 d = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1.0 - u1) * n;
    if (!(d[1] < 0)) continue;
    const double t_floor = -x[1] / d[1];
    const Vec3 p = x + t_floor * d;
    if (p[0] < 0 || p[0] > kRoom || p[2] < 0 || p[2] > kRoom) continue;
    const auto t_block = hit_block(x, d);
    if (t_block && *t_block < t_floor) continue;
    ++floor_hits;
  }
  return static_cast<double>(floor_hits) / rays;
}

TEST(SurfaceTransport, FloorSeenFromTheFootOfAWallPastABlockMatchesTracedRays) {
  // A receiver at the foot of a wall (z = 0, facing +z) sees the floor with
  // F ≈ 1/2; the block hides only what lies behind it. The visible fraction
  // comes from k² = 16 shadow rays: drawn by area and weighted by the kernel
  // (the former estimator), the nearest samples decided it and it read
  // 0.36 against a true 0.50 at x = 2.5.
  TriMesh floor_mesh;
  for (const auto& t : floor_triangles(1)) {
    floor_mesh.add_face(floor_mesh.add_vertex(t[0]), floor_mesh.add_vertex(t[1]), floor_mesh.add_vertex(t[2]));
  }
  const TriMesh block_mesh = block();
  const RayCaster rays({&floor_mesh, &block_mesh});
  const std::vector<std::vector<Vec3>> polygons{
      {Vec3(0, 0, 0), Vec3(0, 0, kRoom), Vec3(kRoom, 0, kRoom), Vec3(kRoom, 0, 0)}};
  const auto triangles = floor_triangles(8);

  for (const Vec3& x : {Vec3(2.5, 0, 0), Vec3(2.0, 0.02, 0), Vec3(1.0, 0.1, 0), Vec3(3.9, 0, 0)}) {
    ReceiverPoint receiver;
    receiver.x = x;
    receiver.normal = Vec3(0, 0, 1);
    receiver.approach = Vec3(0, 1, 0);  // from inside the wall, above the corner
    // The truth is traced from just inside the wall's interior, as the limit is taken.
    const double truth = visible_floor_form_factor(x + Vec3(0, 1e-7, 0), receiver.normal, 400000);
    double worst = 0.0, sum = 0.0;
    constexpr int kPatterns = 24;
    for (int key = 0; key < kPatterns; ++key) {
      TransportSampling sampling;
      sampling.k = 4;
      sampling.key = sample_key(7, static_cast<std::uint64_t>(key));
      std::uint64_t ray_count = 0;
      const TransportCoefficients c = surface_transport(receiver, polygons, triangles, rays, sampling, ray_count);
      EXPECT_GT(ray_count, 0u);
      worst = std::max(worst, std::abs(c.f[0] - truth));
      sum += c.f[0];
    }
    // Noise of 16 rays on a fraction this close to 1 is a few per cent;
    // the mean over patterns must agree with the traced rays (±0.002 at 400 k).
    EXPECT_NEAR(sum / kPatterns, truth, 0.01) << "receiver at " << x;
    EXPECT_LT(worst, 0.05) << "receiver at " << x << ", truth " << truth;
  }
}

TEST(TriangleTransport, AtTheFootOfAWallTheSplitIsTheWallsValueThere) {
  // x on the floor at the foot of a wall triangle, on its bottom edge. As x
  // approaches the edge from inside the floor, all of the wall's form factor
  // comes from ever smaller neighbourhoods of x (points of the wall's plane
  // away from x are seen edge-on), so the linear basis takes it in the
  // proportions of x's own barycentric coordinates: F^l = F N^l(x).
  const std::array<Vec3, 3> wall{Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(0, 3, 0)};  // z = 0, faces +z
  TriMesh mesh;
  mesh.add_face(mesh.add_vertex(wall[0]), mesh.add_vertex(wall[1]), mesh.add_vertex(wall[2]));
  const RayCaster rays({&mesh});
  for (const double along : {0.4, 1.0, 2.1}) {
    ReceiverPoint x;
    x.x = Vec3(along, 0, 0);
    x.normal = Vec3(0, 1, 0);
    x.approach = Vec3(0, 0, 1);
    TransportSampling sampling;
    sampling.key = 7;
    std::uint64_t ray_count = 0;
    const TransportCoefficients c = triangle_transport(x, wall, rays, sampling, ray_count);
    const double total = c.visible();
    ASSERT_NEAR(total, 0.5, 1e-6) << "the wall fills half the floor's projected hemisphere at its foot";
    const std::array<double, 3> hat{1.0 - along / 3.0, along / 3.0, 0.0};
    for (int l = 0; l < 3; ++l) EXPECT_NEAR(c.f[l] / total, hat[l], 0.02) << "corner " << l << " at " << along;
  }
}

// ∫_T N^l(y) V(x, y) cosθx cosθy / (π r²) dy for each corner l of triangle T
// on the floor (normal +y), x of unit normal n: a midpoint rule on T cut
// into 4^depth similar pieces, leaving out the points the block hides.
std::array<double, 3> hat_integrals(const Vec3& x, const Vec3& n, const std::array<Vec3, 3>& t, int depth) {
  std::array<double, 3> out{0.0, 0.0, 0.0};
  const int cuts = 1 << depth;
  const double piece_area = 0.5 * OpenMesh::cross(t[1] - t[0], t[2] - t[0]).norm() / (cuts * cuts);
  const auto add = [&](double a, double b) {  // barycentrics of corners 1 and 2 at a piece's centroid
    const Vec3 y = (1.0 - a - b) * t[0] + a * t[1] + b * t[2];
    const Vec3 d = y - x;
    const double r2 = d.sqrnorm(), r = std::sqrt(r2);
    const double cos_x = OpenMesh::dot(n, d) / r, cos_y = -d[1] / r;
    if (cos_x <= 0 || cos_y <= 0) return;
    const auto blocked = hit_block(x, d / r);
    if (blocked && *blocked < r) return;
    const double k = cos_x * cos_y / (M_PI * r2) * piece_area;
    out[0] += (1.0 - a - b) * k;
    out[1] += a * k;
    out[2] += b * k;
  };
  for (int i = 0; i < cuts; ++i) {
    for (int j = 0; i + j < cuts; ++j) {
      add((i + 1.0 / 3.0) / cuts, (j + 1.0 / 3.0) / cuts);  // upright piece
      if (i + j + 1 < cuts) add((i + 2.0 / 3.0) / cuts, (j + 2.0 / 3.0) / cuts);  // inverted piece
    }
  }
  return out;
}

TEST(TriangleTransport, FourChildrenMergedGiveTheParentsIntegralOfEachHat) {
  // A floor triangle that the block half hides from a point above and
  // beside it. The parent's hat functions are linear on each child, so its
  // three coefficients are fixed sums of the children's twelve: merging
  // them (what coarsening a link does) must give each ∫ N^L V K over the
  // parent, and Σ_L exactly the parent's unoccluded form factor.
  const std::array<Vec3, 3> parent{Vec3(0.5, 0, 0.5), Vec3(0.5, 0, 3.5), Vec3(3.5, 0, 3.5)};
  const TriMesh box = block();
  const RayCaster rays({&box});
  // mesh/hierarchy.hpp's children: 0 = (v0,m01,m20), 1 = (m01,v1,m12),
  // 2 = (m20,m12,v2), 3 = (m12,m20,m01).
  const Vec3 m01 = 0.5 * (parent[0] + parent[1]), m12 = 0.5 * (parent[1] + parent[2]),
             m20 = 0.5 * (parent[2] + parent[0]);
  const std::array<std::array<Vec3, 3>, 4> children{{{parent[0], m01, m20},
                                                     {m01, parent[1], m12},
                                                     {m20, m12, parent[2]},
                                                     {m12, m20, m01}}};
  const Vec3 n = Vec3(0.3, -1.0, 0.2).normalized();
  for (const Vec3& at : {Vec3(3.2, 1.6, 0.9), Vec3(0.2, 2.5, 3.8)}) {
    ReceiverPoint x;
    x.x = at;
    x.normal = n;
    TransportSampling sampling;
    sampling.k = 16;
    std::uint64_t ray_count = 0;
    std::array<TransportCoefficients, 4> parts;
    for (int c = 0; c < 4; ++c) {
      sampling.key = 100 + static_cast<std::uint64_t>(c);
      parts[c] = triangle_transport(x, children[c], rays, sampling, ray_count);
    }
    const TransportCoefficients merged = merge_child_coefficients(parts);
    const std::array<double, 3> truth = hat_integrals(at, n, parent, 9);
    const double total = truth[0] + truth[1] + truth[2];
    ASSERT_GT(total, 0.0);
    EXPECT_NEAR(merged.unoccluded, point_triangle_form_factor(at, n, parent), 1e-5 * merged.unoccluded);
    double hidden = 1.0 - total / merged.unoccluded;
    EXPECT_GT(hidden, 0.05) << "the block must hide part of the triangle for the test to mean anything";
    for (int l = 0; l < 3; ++l) {
      EXPECT_NEAR(merged.f[l], truth[l], 0.02 * total) << "corner " << l << " seen from " << at;
    }
  }
}

// A floor whose triangles hold different values: bright ones in the middle,
// dark ones by the walls, as under a lamp. What a receiver gets from it as
// one constant-basis shooter must be the floor's radiance weighted by that
// receiver's kernel, not the floor's mean times the whole form factor: above
// the bright middle the mean is too low, above a corner too high
// (docs/accuracy.md, "A bright part that sees more"). The truth is a midpoint
// quadrature of the kernel over the floor on a 400 × 400 grid.
double floor_value(const Vec3& y) {
  const double dx = y[0] - 0.5 * kRoom, dz = y[2] - 0.5 * kRoom;
  return std::abs(dx) < 1.0 && std::abs(dz) < 1.0 ? 10.0 : 1.0;
}

// Each floor triangle's value at its centroid and their mean (the
// triangles have equal areas): what a constant-basis floor carries.
struct TriangleValues {
  std::vector<double> value;
  double mean = 0.0;
  template <typename Value>
  TriangleValues(const std::vector<std::array<Vec3, 3>>& triangles, Value at) {
    for (const auto& t : triangles) {
      value.push_back(at((t[0] + t[1] + t[2]) / 3.0));
      mean += value.back() / static_cast<double>(triangles.size());
    }
  }
  ShooterShape shape() const { return {value, mean}; }
};

std::vector<std::vector<Vec3>> whole_floor() {
  return {{Vec3(0, 0, 0), Vec3(0, 0, kRoom), Vec3(kRoom, 0, kRoom), Vec3(kRoom, 0, 0)}};
}

// ∫ value(y) V(x, y) cosθx cosθy / (π r²) dy over the floor, for x of unit
// normal n (cosθx clipped at x's horizon): a midpoint rule on a 400 × 400
// grid, leaving out the points `hidden` says x cannot see.
template <typename Value, typename Hidden>
double floor_seen_from(const Vec3& x, const Vec3& n, Value value, Hidden hidden) {
  constexpr int kGrid = 400;
  const double cell = kRoom / kGrid;
  double sum = 0.0;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const Vec3 y((i + 0.5) * cell, 0, (j + 0.5) * cell);
      if (hidden(y)) continue;
      const Vec3 d = y - x;
      const double r2 = d.sqrnorm(), r = std::sqrt(r2);
      const double cos_x = OpenMesh::dot(n, d) / r;
      if (cos_x > 0) sum += value(y) * cos_x * (x[1] / r) / (M_PI * r2) * cell * cell;
    }
  }
  return sum;
}

const auto kNothingHidden = [](const Vec3&) { return false; };

double seen_from_above(const Vec3& x) { return floor_seen_from(x, Vec3(0, -1, 0), floor_value, kNothingHidden); }

TEST(ClusterTransport, AReceiverGetsTheFloorAsItsOwnKernelWeighsIt) {
  TriMesh floor_mesh;
  const auto triangles = floor_triangles(4);  // 1 × 1 squares: the middle four are bright
  for (const auto& t : triangles) {
    floor_mesh.add_face(floor_mesh.add_vertex(t[0]), floor_mesh.add_vertex(t[1]), floor_mesh.add_vertex(t[2]));
  }
  const RayCaster rays({&floor_mesh});
  const TriangleValues values(triangles, floor_value);
  const ShooterShape shape = values.shape();
  const double mean = values.mean;
  const auto polygons = whole_floor();
  for (const Vec3& x : {Vec3(2.0, 2.7, 2.0), Vec3(0.5, 2.7, 0.5), Vec3(3.6, 1.0, 2.2)}) {
    ReceiverPoint receiver;
    receiver.x = x;
    receiver.normal = Vec3(0, -1, 0);
    TransportSampling sampling;
    sampling.key = 3;
    std::uint64_t ray_count = 0;
    const double truth = seen_from_above(x);
    const TransportCoefficients cluster = cluster_transport(receiver, triangles, rays, sampling, ray_count, &shape);
    EXPECT_NEAR(cluster.f[0] * mean / truth, 1.0, 0.002) << "cluster, receiver at " << x;
    // The whole surface weighs its triangles by a disc estimate away from x.
    const TransportCoefficients surface =
        surface_transport(receiver, polygons, triangles, rays, sampling, ray_count, &shape);
    EXPECT_NEAR(surface.f[0] * mean / truth, 1.0, 0.02) << "surface, receiver at " << x;
    // Without the shape, the mean stands for the floor: far off here.
    const TransportCoefficients plain = cluster_transport(receiver, triangles, rays, sampling, ray_count);
    EXPECT_GT(std::abs(plain.f[0] * mean / truth - 1.0), 0.02) << "receiver at " << x;
  }
}

// A table hides part of the floor from the ceiling, and the part it hides is
// the dark one, its shadow. Weighing every triangle by its form factor
// alone, what the ceiling gets is the mean of a floor that includes the dark
// part, times the fraction it sees: too little. The shadow rays say which
// triangles are hidden (docs/accuracy.md, "A bright part that sees more").
// The truth: a midpoint quadrature of the kernel and the table's shadow over
// the floor on a 400 × 400 grid.
constexpr double kTableLow = 1.5, kTableHigh = 2.5, kTableHeight = 0.75;

double shaded_floor_value(const Vec3& y) {
  return y[0] > kTableLow && y[0] < kTableHigh && y[2] > kTableLow && y[2] < kTableHigh ? 0.1 : 1.0;
}

double seen_past_the_table(const Vec3& x) {
  return floor_seen_from(x, Vec3(0, -1, 0), shaded_floor_value, [&x](const Vec3& y) {
    const Vec3 crossing = x + ((x[1] - kTableHeight) / x[1]) * (y - x);
    return crossing[0] > kTableLow && crossing[0] < kTableHigh && crossing[2] > kTableLow && crossing[2] < kTableHigh;
  });
}

TEST(ClusterTransport, WhatATableHidesIsLeftOutOfTheMeanTheCeilingSees) {
  TriMesh floor_mesh, table;
  const auto triangles = floor_triangles(8);  // 0.5 × 0.5 squares: four of them under the table
  for (const auto& t : triangles) {
    floor_mesh.add_face(floor_mesh.add_vertex(t[0]), floor_mesh.add_vertex(t[1]), floor_mesh.add_vertex(t[2]));
  }
  const auto t00 = table.add_vertex(Vec3(kTableLow, kTableHeight, kTableLow));
  const auto t01 = table.add_vertex(Vec3(kTableLow, kTableHeight, kTableHigh));
  const auto t11 = table.add_vertex(Vec3(kTableHigh, kTableHeight, kTableHigh));
  const auto t10 = table.add_vertex(Vec3(kTableHigh, kTableHeight, kTableLow));
  table.add_face(t00, t01, t11);
  table.add_face(t00, t11, t10);
  const RayCaster rays({&floor_mesh, &table});
  const TriangleValues values(triangles, shaded_floor_value);
  const ShooterShape shape = values.shape();
  const double mean = values.mean;
  const auto polygons = whole_floor();
  for (const Vec3& x : {Vec3(2.0, 2.7, 2.6), Vec3(2.9, 2.7, 2.2), Vec3(1.2, 2.0, 1.0), Vec3(2.0, 1.1, 2.3)}) {
    ReceiverPoint receiver;
    receiver.x = x;
    receiver.normal = Vec3(0, -1, 0);
    const double truth = seen_past_the_table(x);
    // Sixteen shadow rays make any one link's visible fraction noisy
    // (5–7 % here); what must hold is that the noise averages to the truth,
    // over many sample patterns. Weighing the hidden dark part by its form
    // factor, the mean was 3–8 % low at the first three points and 18 % low
    // at the last, just above the table; there the whole surface's rays,
    // counted as drawn (widened toward the far floor), read 16 % high.
    constexpr int kPatterns = 256;
    double cluster_sum = 0.0, surface_sum = 0.0;
    for (std::uint64_t key = 1; key <= kPatterns; ++key) {
      TransportSampling sampling;
      sampling.key = key;
      std::uint64_t ray_count = 0;
      cluster_sum += cluster_transport(receiver, triangles, rays, sampling, ray_count, &shape).f[0];
      surface_sum += surface_transport(receiver, polygons, triangles, rays, sampling, ray_count, &shape).f[0];
    }
    EXPECT_NEAR(cluster_sum / kPatterns * mean / truth, 1.0, 0.015) << "cluster, receiver at " << x;
    // The whole surface weighs its triangles by a disc estimate away from x.
    EXPECT_NEAR(surface_sum / kPatterns * mean / truth, 1.0, 0.025) << "surface, receiver at " << x;
  }
}

// A floor of two triangles seen past a board at half the receiver's height
// that leaves only a far strip in view: each shadow ray must stand for the
// form factor of where it lands, not for a share of its triangle's area.
// Rays drawn to the triangles by form factor but ending uniformly over each
// triangle's area count the strip for its share of the area (3/8 here),
// where its share of the form factor is a fraction of that; the underside of
// a table inside its aprons read 3 % dark that way (docs/accuracy.md,
// "Under the table, light source by light source"). The truth: the strip's
// exact form factor (the board's shadow edge lies on a line of the floor).
TEST(ClusterTransport, AFloorSeenPastABoardGivesTheFormFactorOfTheStripInView) {
  constexpr double kBoard = 2.0;  // the board covers x < 2 at half the receiver's height
  for (const Vec3& x : {Vec3(1.5, 0.4, 2.0), Vec3(1.7, 1.0, 2.0), Vec3(1.9, 0.8, 3.0)}) {
    TriMesh floor_mesh, board;
    const auto triangles = floor_triangles(1);
    for (const auto& t : triangles) {
      floor_mesh.add_face(floor_mesh.add_vertex(t[0]), floor_mesh.add_vertex(t[1]), floor_mesh.add_vertex(t[2]));
    }
    const double h = 0.5 * x[1];
    const auto b0 = board.add_vertex(Vec3(-20, h, -20)), b1 = board.add_vertex(Vec3(-20, h, 20));
    const auto b2 = board.add_vertex(Vec3(kBoard, h, 20)), b3 = board.add_vertex(Vec3(kBoard, h, -20));
    board.add_face(b0, b1, b2);
    board.add_face(b0, b2, b3);
    const RayCaster rays({&floor_mesh, &board});
    // A ray crosses the board's height halfway: it passes the board's edge
    // where it lands at 2·kBoard − x.
    const double edge = 2.0 * kBoard - x[0];
    const std::vector<Vec3> strip{Vec3(edge, 0, 0), Vec3(edge, 0, kRoom), Vec3(kRoom, 0, kRoom), Vec3(kRoom, 0, 0)};
    ReceiverPoint receiver;
    receiver.x = x;
    receiver.normal = Vec3(0, -1, 0);
    const double truth = point_polygon_form_factor(x, receiver.normal, strip);
    const double whole = point_polygon_form_factor(x, receiver.normal, whole_floor()[0]);
    ASSERT_LT(truth, 0.4 * whole) << "the board must hide most of the floor from " << x;
    // The mean over sample patterns against the truth, within four of its
    // standard errors (measured; 0.3–1.6 % here) and half a per cent.
    constexpr int kPatterns = 2048;
    for (const bool whole_surface : {false, true}) {
      double sum = 0.0, sum2 = 0.0;
      for (std::uint64_t key = 1; key <= kPatterns; ++key) {
        TransportSampling sampling;
        sampling.key = key;
        sampling.k = 8;
        std::uint64_t ray_count = 0;
        const double f =
            whole_surface ? surface_transport(receiver, whole_floor(), triangles, rays, sampling, ray_count).f[0]
                          : cluster_transport(receiver, triangles, rays, sampling, ray_count).f[0];
        sum += f;
        sum2 += f * f;
      }
      const double mean = sum / kPatterns;
      const double error = std::sqrt(std::max(0.0, sum2 / kPatterns - mean * mean) / kPatterns);
      EXPECT_NEAR(mean, truth, 4.0 * error + 0.005 * truth)
          << (whole_surface ? "surface" : "cluster") << ", receiver at " << x << ", standard error " << error;
    }
  }
}


// A receiver tilted so that its horizon cuts the floor, as a block's side
// sees the floor it stands on: what it gets from the floor as one planar
// cluster (the form factor clipped to its horizon, ShooterHorizon::kCrossing)
// is the part above the horizon weighted by its kernel. The bright band lies
// mostly below the horizon, so a shooter mean that let that part in would be
// far too high. The truth is a midpoint rule of the kernel, cosθx clipped at the
// horizon, on a 400 × 400 grid; the form factor is the sum of the roots'
// exact (clipped) ones, not the outline's.
TEST(ClusterTransport, AFloorAcrossTheReceiversHorizonGivesWhatIsAboveIt) {
  TriMesh floor_mesh;
  const auto triangles = floor_triangles(16);
  for (const auto& t : triangles) {
    floor_mesh.add_face(floor_mesh.add_vertex(t[0]), floor_mesh.add_vertex(t[1]), floor_mesh.add_vertex(t[2]));
  }
  const RayCaster rays({&floor_mesh});
  const auto value_at = [](const Vec3& y) { return y[0] < 1.25 ? 10.0 : 1.0; };  // on a grid line
  const TriangleValues values(triangles, value_at);
  const ShooterShape shape = values.shape();
  const ShooterTriangleTable table(triangles);
  for (const Vec3& x : {Vec3(2.0, 1.0, 2.0), Vec3(1.6, 0.4, 2.0), Vec3(1.2, 1.0, 3.0)}) {
    ReceiverPoint receiver;
    receiver.x = x;
    receiver.normal = Vec3(1.0, -0.75, 0.1).normalized();
    const double truth = floor_seen_from(x, receiver.normal, value_at, kNothingHidden);
    double ff = 0.0, below = 0.0;
    for (const auto& t : triangles) {
      ff += point_triangle_form_factor(x, receiver.normal, t);
      for (const Vec3& p : t) below = std::min(below, OpenMesh::dot(receiver.normal, p - x));
    }
    ASSERT_LT(below, -0.5) << "the receiver's horizon must cut the floor, at " << x;
    TransportSampling sampling;
    sampling.key = 11;
    std::uint64_t ray_count = 0;
    const TransportCoefficients c = planar_shooter_transport(receiver, ff, ShooterTriangles{&table, {}}, rays, sampling,
                                                             ray_count, &shape, ShooterHorizon::kCrossing);
    EXPECT_FLOAT_EQ(c.unoccluded, static_cast<float>(ff));
    EXPECT_NEAR(c.f[0] * values.mean / truth, 1.0, 0.01) << "receiver at " << x;
  }
}

// A cluster of a curved shooter that the receiver sees plainly takes its
// exact form factor from its outline and draws its rays by disc estimates
// with each root's own normal (docs/design.md, "Cluster outlines"); the
// cluster link that takes every root's exact form factor is the truth. The
// shooter is a floor bent up into a quarter cylinder, brighter along one
// side and at one end of the bend; where a root is behind the receiver or
// below its horizon, the outline does not hold and nothing is returned.
TEST(ClusterTransport, ACurvedClusterSeenPlainlyAgreesWithItsRootsOneByOne) {
  constexpr int kCells = 8;
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> vh;
  for (int j = 0; j <= kCells; ++j) {
    for (int i = 0; i <= kCells; ++i) {
      const double angle = 0.5 * M_PI * i / kCells;
      vh.push_back(mesh.add_vertex(Vec3(4.0 * std::sin(angle), 4.0 * (1.0 - std::cos(angle)), 0.5 * j)));
    }
  }
  for (int j = 0; j < kCells; ++j) {
    for (int i = 0; i < kCells; ++i) {
      const auto a = vh[j * (kCells + 1) + i], b = vh[j * (kCells + 1) + i + 1];
      const auto c = vh[(j + 1) * (kCells + 1) + i + 1], d = vh[(j + 1) * (kCells + 1) + i];
      mesh.add_face(a, c, b);
      mesh.add_face(a, d, c);
    }
  }
  const SurfaceHierarchy h(mesh);
  std::vector<std::array<Vec3, 3>> triangles;
  std::vector<RootCluster> clusters(1);
  for (std::size_t f = 0; f < h.num_roots(); ++f) {
    const auto& c = h.corners(h.root(static_cast<int>(f)));
    triangles.push_back({h.point(c[0]), h.point(c[1]), h.point(c[2])});
    clusters[0].roots.push_back(static_cast<NodeId>(f));
  }
  ASSERT_GT(OpenMesh::dot(OpenMesh::cross(triangles[0][1] - triangles[0][0], triangles[0][2] - triangles[0][0]),
                          Vec3(-1, 1, 0)),
            0.0)
      << "the shooter must face the inside of its bend";
  const ClusterOutlines outlines = cluster_outlines(h, clusters, root_corner_edges(h), 1);
  const std::span<const Vec3> points(h.mesh().points(), h.mesh().n_vertices());
  const ShooterTriangleTable table(triangles);
  const ShooterTriangles shooter{&table, {}};
  const RayCaster rays({&h.mesh()});
  const TriangleValues values(triangles,
                              [](const Vec3& y) { return (y[1] < 1.2 ? 4.0 : 1.0) * (y[2] < 1.5 ? 2.0 : 1.0); });
  const ShooterShape shape = values.shape();
  const Vec3 inward = Vec3(-1, 1, 0).normalized();
  struct Case {
    Vec3 x, normal;
  };
  // Inside the bend, facing it: every root in front and above the horizon.
  for (const Case& r : {Case{Vec3(0.5, 3.5, 2.0), -inward}, Case{Vec3(1.0, 3.0, 1.0), Vec3(1, -1, 0.2)},
                        Case{Vec3(1.5, 2.5, 3.5), Vec3(1, -1, -0.3)}}) {
    ReceiverPoint receiver;
    receiver.x = r.x;
    receiver.normal = r.normal.normalized();
    double worst_unoccluded = 0.0, curved_sum = 0.0, exact_sum = 0.0;
    constexpr int kPatterns = 64;
    for (int key = 1; key <= kPatterns; ++key) {
      TransportSampling sampling;
      sampling.key = static_cast<std::uint64_t>(key);
      std::uint64_t ray_count = 0;
      const std::optional<TransportCoefficients> curved =
          curved_cluster_transport(receiver, shooter, points, outlines.of(0), rays, sampling, ray_count, &shape);
      ASSERT_TRUE(curved.has_value()) << "receiver at " << r.x << " sees every root plainly";
      const TransportCoefficients exact =
          cluster_transport(receiver, shooter, rays, sampling, ray_count, &shape, root_corner_edges(h));
      worst_unoccluded = std::max(worst_unoccluded, std::abs(curved->unoccluded / exact.unoccluded - 1.0));
      curved_sum += curved->f[0];
      exact_sum += exact.f[0];
    }
    EXPECT_LT(worst_unoccluded, 1e-6) << "receiver at " << r.x;
    // The shares differ only where the disc estimates do: far roots.
    EXPECT_NEAR(curved_sum / exact_sum, 1.0, 0.01) << "receiver at " << r.x;
  }
  // Roots below the horizon (a receiver tilted away from part of the
  // bend), or behind the receiver (outside the bend): the roots are taken
  // one by one instead.
  for (const Case& r : {Case{Vec3(0.5, 3.5, 2.0), Vec3(0, -1, 0)}, Case{Vec3(5.0, -1.0, 2.0), inward}}) {
    ReceiverPoint receiver;
    receiver.x = r.x;
    receiver.normal = r.normal.normalized();
    TransportSampling sampling;
    std::uint64_t ray_count = 0;
    EXPECT_FALSE(curved_cluster_transport(receiver, shooter, points, outlines.of(0), rays, sampling, ray_count, &shape))
        << "receiver at " << r.x;
  }
}

// SharedLinkGeometry (transport.hpp): a link's draws made inside a scope,
// which work their geometry out once per receiver point, give exactly what
// the same draws give outside one, for every kind of shooter, with two
// receiver points drawn in turn in one scope as a curved receiver's
// collocation points are.
TEST(SharedLinkGeometry, DrawsInsideAScopeEqualTheSameDrawsOutsideOne) {
  TriMesh floor_mesh;
  for (const auto& t : floor_triangles(1)) {
    floor_mesh.add_face(floor_mesh.add_vertex(t[0]), floor_mesh.add_vertex(t[1]), floor_mesh.add_vertex(t[2]));
  }
  const TriMesh block_mesh = block();
  const RayCaster rays({&floor_mesh, &block_mesh});
  const auto triangles = floor_triangles(8);
  const ShooterTriangleTable table(triangles);
  const ShooterTriangles whole{&table, {}};
  const TriangleValues values(triangles, floor_value);
  const ShooterShape shape = values.shape();
  const auto polygons = whole_floor();
  std::vector<ReceiverPoint> receivers(2);
  receivers[0].x = Vec3(2.5, 0, 0);  // at the foot of a wall: near triangles, the block between
  receivers[0].normal = Vec3(0, 0, 1);
  receivers[0].approach = Vec3(0, 1, 0);
  receivers[1].x = Vec3(1.0, 2.0, 3.0);  // above the floor, facing it at a slant
  receivers[1].normal = Vec3(0.3, -1, -0.2).normalized();
  // Each kind of shooter, drawn for one receiver with one sampling.
  const std::vector<std::function<TransportCoefficients(const ReceiverPoint&, const TransportSampling&,
                                                        std::uint64_t&)>>
      kinds = {
          [&](const ReceiverPoint& r, const TransportSampling& s, std::uint64_t& n) {
            return triangle_transport(r, triangles[13], rays, s, n);
          },
          [&](const ReceiverPoint& r, const TransportSampling& s, std::uint64_t& n) {
            return cluster_transport(r, whole, rays, s, n, &shape);
          },
          [&](const ReceiverPoint& r, const TransportSampling& s, std::uint64_t& n) {
            return surface_transport(r, polygons, whole, rays, s, n, &shape);
          },
          [&](const ReceiverPoint& r, const TransportSampling& s, std::uint64_t& n) {
            return planar_shooter_transport(r, 0.25, whole, rays, s, n, &shape, ShooterHorizon::kCrossing);
          },
      };
  TransportSampling pilot, second;
  pilot.k = 4;
  pilot.key = sample_key(3, 1);
  second.k = 9;
  second.key = sample_key(3, 2);
  for (std::size_t kind = 0; kind < kinds.size(); ++kind) {
    std::vector<TransportCoefficients> alone, shared;
    std::uint64_t alone_rays = 0, shared_rays = 0;
    for (const TransportSampling& s : {pilot, second}) {
      for (const ReceiverPoint& r : receivers) alone.push_back(kinds[kind](r, s, alone_rays));
    }
    {
      const SharedLinkGeometry scope;
      for (const TransportSampling& s : {pilot, second}) {
        for (const ReceiverPoint& r : receivers) shared.push_back(kinds[kind](r, s, shared_rays));
      }
    }
    EXPECT_EQ(shared_rays, alone_rays) << "kind " << kind;
    ASSERT_EQ(shared.size(), alone.size());
    for (std::size_t i = 0; i < alone.size(); ++i) {
      EXPECT_GT(alone[i].unoccluded, 0.0f) << "kind " << kind << ", draw " << i << " must see the floor";
      EXPECT_EQ(shared[i].unoccluded, alone[i].unoccluded) << "kind " << kind << ", draw " << i;
      for (int l = 0; l < 3; ++l) EXPECT_EQ(shared[i].f[l], alone[i].f[l]) << "kind " << kind << ", draw " << i;
    }
  }
}

// What one scope worked out is not read by the next, nor by one opened
// inside it: another shooter drawn for the same receiver point gets its own
// geometry.
TEST(SharedLinkGeometry, AClosedOrOuterScopeLeavesNothingForTheNextShooter) {
  const TriMesh empty;
  const RayCaster rays({&empty});
  const auto triangles = floor_triangles(2);
  ReceiverPoint receiver;
  receiver.x = Vec3(1.0, 1.0, 1.0);
  receiver.normal = Vec3(0, -1, 0);
  TransportSampling sampling;
  std::uint64_t n = 0;
  TransportCoefficients first;
  {
    const SharedLinkGeometry scope;
    first = triangle_transport(receiver, triangles[0], rays, sampling, n);
  }
  const SharedLinkGeometry scope;
  const TransportCoefficients other = triangle_transport(receiver, triangles[5], rays, sampling, n);
  const double exact = point_triangle_form_factor(receiver.x, receiver.normal, triangles[5]);
  EXPECT_NE(first.unoccluded, other.unoccluded);
  EXPECT_NEAR(other.unoccluded, exact, 1e-6 * exact);
  {
    // A scope opened inside this one (another link's task run on this
    // thread while it waits) starts empty, and leaves this one's entries.
    const SharedLinkGeometry inner;
    const TransportCoefficients nested = triangle_transport(receiver, triangles[0], rays, sampling, n);
    EXPECT_EQ(nested.unoccluded, first.unoccluded);
  }
  EXPECT_EQ(triangle_transport(receiver, triangles[5], rays, sampling, n).unoccluded, other.unoccluded);
}

}  // namespace
}  // namespace lhr
