// A planar surface's initial mesh (mesh/planar_mesh.hpp; docs/design.md §4):
// constrained Delaunay refinement of the surface's region. Every check
// compares against a property of the input computed here independently
// (areas, boundary, topology, closed-form angles), never against a previous
// run's numbers.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/initial_mesh.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

using namespace test;

// Maps (x, y) in the plane spanned by e1, e2 through o.
struct Plane {
  Vec3 o{0, 0, 0}, e1{1, 0, 0}, e2{0, 1, 0};
  Vec3 at(double x, double y) const { return o + x * e1 + y * e2; }
};

Plane tilted_plane() {
  Plane p;
  p.o = Vec3(0.3, -1.2, 2.5);
  p.e1 = Vec3(2.0, 1.0, -2.0) / 3.0;   // unit
  p.e2 = Vec3(1.0, 2.0, 2.0) / 3.0;    // unit, orthogonal to e1
  return p;
}

// L-shape (2x2 minus the top-right 1x1) as one non-convex polygon, in a tilted plane.
Surface l_shape() {
  const Plane pl = tilted_plane();
  return make_surface("L",
                      {pl.at(0, 0), pl.at(2, 0), pl.at(2, 1), pl.at(1, 1), pl.at(1, 2), pl.at(0, 2)},
                      {{0, 1, 2, 3, 4, 5}}, true);
}

// [0,3]^2 with the hole [1,2]^2, as four trapezoids around it.
Surface square_with_hole() {
  std::vector<Vec3> p = {{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {0, 3, 0},   // outer 0..3
                         {1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}};  // inner 4..7
  return make_surface("frame", p, {{0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}, true);
}

Surface strip() {
  return make_surface("strip", {{0, 0, 0}, {1, 0, 0}, {1, 0.01, 0}, {0, 0.01, 0}}, {{0, 1, 2, 3}}, true);
}

// The Cornell box's published left wall: one quad whose corners are up to a
// few mm off a common plane (units mm).
Surface cornell_left_wall() {
  return make_surface("left_wall",
                      {{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}},
                      {{0, 1, 2, 3}}, true);
}

// Isosceles triangle with a 10 degree apex: an input angle the mesher cannot improve.
Surface thin_wedge() {
  const double half = 5.0 * kPi / 180.0;
  return make_surface("wedge", {{0, 0, 0}, {std::cos(half), -std::sin(half), 0}, {std::cos(half), std::sin(half), 0}},
                      {{0, 1, 2}}, true);
}


double size_of(const Surface& s) {
  Vec3 lo = s.points[0], hi = s.points[0];
  for (const Vec3& p : s.points) {
    lo.minimize(p);
    hi.maximize(p);
  }
  return (hi - lo).norm();
}

// Interior angle of the surface's region at each input vertex: the sum of the
// polygon corner angles there.
std::map<int, double> region_angles(const Surface& s) {
  std::map<int, double> angle;
  for (const auto& poly : s.polygons) {
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 p = s.points[poly[i]];
      const Vec3 a = s.points[poly[(i + n - 1) % n]] - p;
      const Vec3 b = s.points[poly[(i + 1) % n]] - p;
      double corner = std::atan2(OpenMesh::dot(OpenMesh::cross(b, a), s.normal), OpenMesh::dot(a, b));
      if (corner < 0) corner += 2 * kPi;  // reflex corner
      angle[poly[i]] += corner;
    }
  }
  return angle;
}

// Everything the planar contract promises; euler = V - E + F of the region
// (1 for a disk, 0 for an annulus).
void check_planar(const Surface& s, const MeshingOptions& options, const TriMesh& m, int euler) {
  SCOPED_TRACE("surface " + s.name);
  ASSERT_GT(m.n_faces(), 0u);
  const double size = size_of(s);

  // Edge lengths.
  EXPECT_LE(max_edge_length(m), options.max_edge * (1 + 1e-9));

  // Area: the piecewise-linear input exactly.
  EXPECT_NEAR(mesh_area(m), fan_area(s), 1e-9 * fan_area(s));

  // Orientation: every face counter-clockwise seen from the front.
  for (const auto f : m.faces()) {
    const auto c = corners(m, f);
    EXPECT_GT(OpenMesh::dot(OpenMesh::cross(c[1] - c[0], c[2] - c[0]), s.normal), 0.0);
  }

  // Topology: manifold region of the expected type, no duplicates.
  EXPECT_EQ(static_cast<int>(m.n_vertices()) - static_cast<int>(m.n_edges()) + static_cast<int>(m.n_faces()), euler);
  for (const auto v : m.vertices()) EXPECT_TRUE(m.is_manifold(v));
  expect_no_duplicate_vertices(m);

  // Input boundary vertices kept bit for bit.
  std::set<std::array<double, 3>> out_points;
  for (const auto v : m.vertices()) out_points.insert({m.point(v)[0], m.point(v)[1], m.point(v)[2]});
  for (int i : input_boundary_vertices(s)) {
    const Vec3& p = s.points[i];
    EXPECT_TRUE(out_points.count({p[0], p[1], p[2]})) << "input boundary vertex " << i << " moved or lost";
  }

  // Output boundary lies on the input boundary and covers it.
  const std::vector<Segment> boundary = input_boundary(s);
  double input_length = 0.0, output_length = 0.0;
  for (const Segment& seg : boundary) input_length += (seg.b - seg.a).norm();
  for (const auto h : m.halfedges()) {
    if (!m.is_boundary(h)) continue;
    const Vec3 a = m.point(m.from_vertex_handle(h)), b = m.point(m.to_vertex_handle(h));
    output_length += (b - a).norm();
    bool on_input = false;
    for (const Segment& seg : boundary) {
      on_input = on_input || (distance_to_segment(a, seg) < 1e-9 * size && distance_to_segment(b, seg) < 1e-9 * size &&
                              distance_to_segment(0.5 * (a + b), seg) < 1e-9 * size);
    }
    EXPECT_TRUE(on_input) << "boundary edge " << a << " - " << b << " is not on the input boundary";
  }
  EXPECT_NEAR(output_length, input_length, 1e-9 * input_length);

  // Angles, except next to input corners sharper than twice the bound.
  const double bound = std::min(options.min_angle_deg, deg(std::asin(std::sqrt(0.125))));
  const std::map<int, double> corner_angle = region_angles(s);
  std::set<std::array<double, 3>> sharp;
  for (int i : input_boundary_vertices(s)) {
    if (deg(corner_angle.at(i)) < 2 * options.min_angle_deg) sharp.insert({s.points[i][0], s.points[i][1], s.points[i][2]});
  }
  for (const auto f : m.faces()) {
    const auto c = corners(m, f);
    bool exempt = false;
    for (const Vec3& p : c) exempt = exempt || sharp.count({p[0], p[1], p[2]});
    if (!exempt) {
      EXPECT_GE(deg(smallest_angle(c)), bound - 1e-6) << "triangle " << c[0] << " | " << c[1] << " | " << c[2];
    }
  }
}

// ---------------------------------------------------------------------------
// Planar surfaces.

TEST(PlanarMeshing, UnitSquare) {
  const Surface s = unit_square();
  const MeshingOptions o = with_h(0.1);
  const TriMesh m = mesh_surface(s, o);
  check_planar(s, o, m, 1);
  // A mesh with edges <= h needs at least area / (sqrt(3)/4 h^2) triangles.
  EXPECT_GE(m.n_faces(), static_cast<std::size_t>(1.0 / (std::sqrt(3.0) / 4 * 0.01)));
}

TEST(PlanarMeshing, NonConvexLShapeInTiltedPlane) {
  const Surface s = l_shape();
  const MeshingOptions o = with_h(0.25);
  check_planar(s, o, mesh_surface(s, o), 1);
  EXPECT_NEAR(fan_area(s), 3.0, 1e-12);  // the truth itself: 2x2 minus 1x1
}

TEST(PlanarMeshing, HoleStaysEmpty) {
  const Surface s = square_with_hole();
  const MeshingOptions o = with_h(0.3);
  const TriMesh m = mesh_surface(s, o);
  check_planar(s, o, m, 0);
  EXPECT_NEAR(mesh_area(m), 8.0, 1e-9 * 8.0);
  for (const auto f : m.faces()) {
    const auto c = corners(m, f);
    const Vec3 centroid = (c[0] + c[1] + c[2]) / 3.0;
    EXPECT_FALSE(centroid[0] > 1 && centroid[0] < 2 && centroid[1] > 1 && centroid[1] < 2) << "face in the hole";
  }
  for (const auto v : m.vertices()) {
    const Vec3& p = m.point(v);
    EXPECT_FALSE(p[0] > 1 && p[0] < 2 && p[1] > 1 && p[1] < 2) << "vertex in the hole: " << p;
  }
}

TEST(PlanarMeshing, ThinStripKeepsAnglesAndSize) {
  const Surface s = strip();
  const MeshingOptions o = with_h(0.1);
  check_planar(s, o, mesh_surface(s, o), 1);
}

TEST(PlanarMeshing, FineCoplanarTessellationIsCoarsenedToH) {
  // Unit square as a 16x16 grid of quads in a tilted plane: interior grid
  // vertices carry no shape, so h = 0.5 must not inherit the grid's density.
  const Plane pl = tilted_plane();
  constexpr int kN = 16;
  std::vector<Vec3> p;
  for (int j = 0; j <= kN; ++j) {
    for (int i = 0; i <= kN; ++i) p.push_back(pl.at(static_cast<double>(i) / kN, static_cast<double>(j) / kN));
  }
  std::vector<std::vector<int>> quads;
  for (int j = 0; j < kN; ++j) {
    for (int i = 0; i < kN; ++i) {
      const int a = j * (kN + 1) + i;
      quads.push_back({a, a + 1, a + kN + 2, a + kN + 1});
    }
  }
  const Surface s = make_surface("grid", p, quads, true);
  const MeshingOptions o = with_h(0.5);
  const TriMesh m = mesh_surface(s, o);
  check_planar(s, o, m, 1);
  EXPECT_LT(m.n_faces(), static_cast<std::size_t>(2 * kN * kN));
}

TEST(PlanarMeshing, RotatedFramesWithSubdividedEdges) {
  // The frame with a hole, every edge subdivided into collinear pieces, in
  // planes of many orientations: projection rounding makes the collinear
  // boundary vertices zigzag by ~1e-16, which must neither break the domain
  // nor stall the refinement.
  for (int r = 0; r < 12; ++r) {
    const double a = 0.37 + 0.61 * r, b = 1.1 + 0.29 * r;
    Plane pl;
    pl.o = Vec3(0.1 * r, -0.2 * r, 0.3);
    const Vec3 n(std::cos(a) * std::sin(b), std::sin(a) * std::sin(b), std::cos(b));
    pl.e1 = OpenMesh::cross(n, Vec3(0.3, -0.5, 0.8)).normalized();
    pl.e2 = OpenMesh::cross(n, pl.e1);
    std::vector<Vec3> p;
    auto ring = [&](double lo, double hi, int pieces) {
      std::vector<int> idx;
      const double corners[4][2] = {{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}};
      for (int c = 0; c < 4; ++c) {
        for (int k = 0; k < pieces; ++k) {
          const double t = static_cast<double>(k) / pieces;
          const double x = corners[c][0] + t * (corners[(c + 1) % 4][0] - corners[c][0]);
          const double y = corners[c][1] + t * (corners[(c + 1) % 4][1] - corners[c][1]);
          idx.push_back(static_cast<int>(p.size()));
          p.push_back(pl.at(x, y));
        }
      }
      return idx;
    };
    const std::vector<int> outer = ring(0.0, 3.0, 6), inner = ring(1.0, 2.0, 2);
    // Four trapezoids: side c of the outer ring (6 pieces) to side c of the inner ring (2 pieces).
    std::vector<std::vector<int>> polys;
    for (int c = 0; c < 4; ++c) {
      std::vector<int> poly;
      for (int k = 0; k <= 6; ++k) poly.push_back(outer[(6 * c + k) % 24]);
      for (int k = 2; k >= 0; --k) poly.push_back(inner[(2 * c + k) % 8]);
      polys.push_back(poly);
    }
    const Surface s = make_surface("rotated_frame_" + std::to_string(r), p, polys, true);
    const MeshingOptions o = with_h(0.2 + 0.05 * r);
    const TriMesh m = mesh_surface(s, o);
    check_planar(s, o, m, 0);
    EXPECT_NEAR(mesh_area(m), 8.0, 1e-9 * 8.0);
  }
}

TEST(PlanarMeshing, NonPlanarCornellWallKeepsItsPiecewiseLinearShape) {
  const Surface s = cornell_left_wall();
  // The quad really is off-plane: corner 2 is off the plane of corners 0, 1, 3.
  const Vec3 n013 = OpenMesh::cross(s.points[1] - s.points[0], s.points[3] - s.points[0]).normalized();
  ASSERT_GT(std::abs(OpenMesh::dot(s.points[2] - s.points[0], n013)), 1.0);

  const MeshingOptions o = with_h(40.0);
  const TriMesh m = mesh_surface(s, o);
  check_planar(s, o, m, 1);
  // Every vertex lies on one of the two fan triangles (0,1,2), (0,2,3).
  const std::array<std::array<int, 3>, 2> fan = {{{0, 1, 2}, {0, 2, 3}}};
  for (const auto v : m.vertices()) {
    const Vec3& p = m.point(v);
    double best = 1e300;
    for (const auto& t : fan) {
      const Vec3 a = s.points[t[0]], b = s.points[t[1]], c = s.points[t[2]];
      const Vec3 nt = OpenMesh::cross(b - a, c - a).normalized();
      // Inside the triangle's prism, distance to its plane.
      const bool inside = OpenMesh::dot(OpenMesh::cross(b - a, p - a), nt) >= -1e-9 &&
                          OpenMesh::dot(OpenMesh::cross(c - b, p - b), nt) >= -1e-9 &&
                          OpenMesh::dot(OpenMesh::cross(a - c, p - c), nt) >= -1e-9;
      if (inside) best = std::min(best, std::abs(OpenMesh::dot(p - a, nt)));
    }
    EXPECT_LT(best, 1e-9 * size_of(s)) << "vertex " << p << " is off the input surface";
  }
}

TEST(PlanarMeshing, SharpInputAngleIsTheOnlyException) {
  const Surface s = thin_wedge();
  const MeshingOptions o = with_h(0.1);
  check_planar(s, o, mesh_surface(s, o), 1);
}

TEST(PlanarMeshing, MinAngleAboveTerminationBoundIsClamped) {
  const Surface s = unit_square();
  MeshingOptions o = with_h(0.2);
  o.min_angle_deg = 30.0;
  const TriMesh m = mesh_surface(s, o);
  check_planar(s, o, m, 1);  // checks against the clamped 20.7 degrees
}

TEST(PlanarMeshing, Deterministic) {
  for (const Surface& s : {square_with_hole(), cornell_left_wall(), l_shape()}) {
    const MeshingOptions o = with_h(s.name == "left_wall" ? 50.0 : 0.2);
    const TriMesh a = mesh_surface(s, o);
    const TriMesh b = mesh_surface(s, o);
    ASSERT_EQ(a.n_vertices(), b.n_vertices());
    ASSERT_EQ(a.n_faces(), b.n_faces());
    for (const auto v : a.vertices()) EXPECT_EQ(a.point(v), b.point(v));
    for (const auto f : a.faces()) {
      auto ia = a.cfv_iter(f);
      auto ib = b.cfv_iter(f);
      for (int k = 0; k < 3; ++k, ++ia, ++ib) EXPECT_EQ(ia->idx(), ib->idx());
    }
  }
}

// ---------------------------------------------------------------------------
// The bundled Cornell box, each input face its own surface, at the default h.

std::vector<Surface> cornell_faces() {
  std::ifstream in(test::source_dir() / "data" / "cornell" / "cornell.obj");
  std::vector<Vec3> v;
  std::vector<Surface> out;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      Vec3 p;
      ls >> p[0] >> p[1] >> p[2];
      v.push_back(p);
    } else if (tag == "f") {
      std::vector<Vec3> pts;
      std::vector<int> poly;
      std::string idx;
      while (ls >> idx) {
        pts.push_back(v.at(std::stoi(idx) - 1));
        poly.push_back(static_cast<int>(poly.size()));
      }
      out.push_back(make_surface("face" + std::to_string(out.size()), pts, {poly}, true));
    }
  }
  return out;
}

TEST(PlanarMeshing, CornellBoxAtDefaultSizeIsFast) {
  const std::vector<Surface> faces = cornell_faces();
  ASSERT_GE(faces.size(), 10u);
  Scene scene;
  scene.surfaces = faces;
  const MeshingOptions o = with_h(default_max_edge(scene));
  const auto start = std::chrono::steady_clock::now();
  std::vector<TriMesh> meshes;
  for (const Surface& s : faces) meshes.push_back(mesh_surface(s, o));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 1.0);
  for (std::size_t i = 0; i < faces.size(); ++i) check_planar(faces[i], o, meshes[i], 1);
}

// A planar surface of 10^5 input triangles is meshed in steps of a tenth of
// a second each: the mesher calls the checkpoint in its passes over the
// input and around CGAL's refinement, and what it throws leaves
// mesh_surface as it was thrown (docs/robustness.md, "Interrupted runs").
TEST(PlanarMeshing, ALargeSurfaceCallsTheCheckpointAndWhatItThrowsPassesThrough) {
  constexpr int kSide = 160;
  Surface s;
  s.name = "grid";
  s.planar = true;
  s.normal = Vec3(0, 1, 0);
  for (int j = 0; j < kSide; ++j) {
    for (int i = 0; i < kSide; ++i) s.points.emplace_back(i, 0, j);
  }
  for (int j = 0; j + 1 < kSide; ++j) {
    for (int i = 0; i + 1 < kSide; ++i) {
      const int a = j * kSide + i, b = a + 1, c = a + kSide, d = c + 1;
      s.polygons.push_back({a, c, d});
      s.polygons.push_back({a, d, b});
    }
  }
  s.area = (kSide - 1.0) * (kSide - 1.0);
  MeshingOptions o = with_h(40.0);
  int calls = 0;
  o.checkpoint = [&] { ++calls; };
  const TriMesh mesh = mesh_surface(s, o);
  EXPECT_GT(mesh.n_faces(), 0u);
  // Ticks every 16 384 items in five passes over ~50 000 triangles and
  // ~75 000 edges, and three calls between the steps.
  EXPECT_GE(calls, 10);
  struct Stop {};
  for (const int stop_at : {1, calls / 2, calls}) {
    int seen = 0;
    o.checkpoint = [&] {
      if (++seen == stop_at) throw Stop{};
    };
    EXPECT_THROW(mesh_surface(s, o), Stop) << "stopped at call " << stop_at;
    EXPECT_EQ(seen, stop_at) << "nothing ran the checkpoint after it threw";
  }
}

}  // namespace
}  // namespace lhr
