// Point-to-polygon form factors against closed forms from Howell's catalogue
// of radiation configuration factors.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <span>
#include <random>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "radiosity/form_factor.hpp"
#include "radiosity/root_clusters.hpp"
#include "radiosity/sampling.hpp"

namespace lhr {
namespace {

// Howell B-2: element parallel to a rectangle a×b at distance c, on the
// normal through one corner.
double howell_parallel_corner(double a, double b, double c) {
  const double A = a / c, B = b / c;
  const double sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
  return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2 * M_PI);
}

// Howell B-3: element in a plane perpendicular to a rectangle (side a along
// the planes' intersection, side b away from the element's plane), on the
// normal to the rectangle through one corner, at distance c.
double howell_perpendicular_corner(double a, double b, double c) {
  const double X = b / a, Y = c / a;
  const double r = std::sqrt(X * X + Y * Y);
  return (std::atan(1 / Y) - Y / r * std::atan(1 / r)) / (2 * M_PI);
}

// Rectangle facing −z (front toward a receiver below), counter-clockwise from the front.
std::vector<Vec3> rectangle_facing_down(double a, double b, double z) {
  return {Vec3(0, 0, z), Vec3(0, b, z), Vec3(a, b, z), Vec3(a, 0, z)};
}

TEST(FormFactor, ParallelRectangleMatchesHowell) {
  for (const auto& [a, b, c] : {std::array{1.0, 1.0, 1.0}, std::array{1.3, 0.7, 0.9},
                                std::array{5.0, 0.2, 0.3}, std::array{0.01, 0.02, 1.0}}) {
    const auto rect = rectangle_facing_down(a, b, c);
    const double f = point_polygon_form_factor(Vec3(0, 0, 0), Vec3(0, 0, 1), rect);
    EXPECT_NEAR(f, howell_parallel_corner(a, b, c), 1e-6) << a << " " << b << " " << c;
  }
}

TEST(FormFactor, PerpendicularRectangleMatchesHowell) {
  for (const auto& [a, b, c] : {std::array{1.0, 1.0, 1.0}, std::array{1.3, 0.7, 0.9},
                                std::array{0.2, 3.0, 0.05}}) {
    // Rectangle in the plane y = c, x ∈ [0,a], z ∈ [0,b], facing −y toward the element at the origin.
    const std::vector<Vec3> rect{Vec3(0, c, 0), Vec3(a, c, 0), Vec3(a, c, b), Vec3(0, c, b)};
    const double f = point_polygon_form_factor(Vec3(0, 0, 0), Vec3(0, 0, 1), rect);
    EXPECT_NEAR(f, howell_perpendicular_corner(a, b, c), 1e-6) << a << " " << b << " " << c;
  }
}

TEST(FormFactor, TrianglesOfARectangleAddUp) {
  const auto rect = rectangle_facing_down(1.3, 0.7, 0.9);
  const Vec3 x(0.2, -0.4, 0.0), n(0, 0, 1);
  const double whole = point_polygon_form_factor(x, n, rect);
  const double halves = point_triangle_form_factor(x, n, {rect[0], rect[1], rect[2]}) +
                        point_triangle_form_factor(x, n, {rect[0], rect[2], rect[3]});
  EXPECT_NEAR(whole, halves, 1e-12);
}

TEST(FormFactor, BackFacingAndBelowTheHorizonGiveZero) {
  const auto down = rectangle_facing_down(1, 1, 1);
  const std::vector<Vec3> up(down.rbegin(), down.rend());
  EXPECT_EQ(point_polygon_form_factor(Vec3(0.5, 0.5, 0), Vec3(0, 0, 1), up), 0.0);
  EXPECT_EQ(point_polygon_form_factor(Vec3(0.5, 0.5, 2), Vec3(0, 0, 1), down), 0.0);
}

TEST(FormFactor, ClipsThePartBelowTheTangentPlane) {
  // A wall crossing the receiver's plane: only the part above it counts,
  // so the answer is Howell B-3 for the upper half.
  const double a = 1.0, b = 0.8, c = 0.6;
  const std::vector<Vec3> wall{Vec3(0, c, -b), Vec3(a, c, -b), Vec3(a, c, b), Vec3(0, c, b)};  // faces −y
  EXPECT_NEAR(point_polygon_form_factor(Vec3(0, 0, 0), Vec3(0, 0, 1), wall), howell_perpendicular_corner(a, b, c),
              1e-9);
}

TEST(FormFactor, WallFloorCornerIsTheFiniteLimit) {
  // Floor point on the base of a wall (x on the shooter's plane and edge):
  // Howell B-3 with c → 0 gives 1/4 at the base's end and 1/2 inside it.
  const std::vector<Vec3> wall{Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 0, 0)};  // faces +y
  const Vec3 up(0, 0, 1);
  const double inside = point_polygon_form_factor(Vec3(0.5, 0, 0), up, wall);
  const double end = point_polygon_form_factor(Vec3(0, 0, 0), up, wall);
  EXPECT_TRUE(std::isfinite(inside));
  EXPECT_TRUE(std::isfinite(end));
  // The exact limit for the square: two B-3 rectangles 0.5×1 at distance → 0.
  EXPECT_NEAR(inside, 2 * howell_perpendicular_corner(0.5, 1.0, 1e-12), 1e-6);
  EXPECT_NEAR(end, howell_perpendicular_corner(1.0, 1.0, 1e-12), 1e-6);
  // Continuity: points approaching along the floor converge to the same value.
  EXPECT_NEAR(point_polygon_form_factor(Vec3(0.5, 1e-7, 0), up, wall), inside, 1e-5);
  // Behind the wall the floor sees its back: nothing.
  EXPECT_EQ(point_polygon_form_factor(Vec3(0.5, -1e-7, 0), up, wall), 0.0);
}

TEST(FormFactor, CoplanarShooterContributesNothing) {
  const std::vector<Vec3> tile{Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(3, 1, 0), Vec3(2, 1, 0)};  // faces +z
  EXPECT_EQ(point_polygon_form_factor(Vec3(0, 0, 0), Vec3(0, 0, 1), tile), 0.0);
  EXPECT_EQ(point_polygon_form_factor(Vec3(2, 0.5, 0), Vec3(0, 0, 1), tile), 0.0);
}

TEST(FormFactor, HemisphereCoveringPolygonApproachesOne) {
  // A huge parallel square centred over x: F → 1 as it grows.
  const double s = 1e4;
  const std::vector<Vec3> big{Vec3(-s, -s, 1), Vec3(-s, s, 1), Vec3(s, s, 1), Vec3(s, -s, 1)};
  const double f = point_polygon_form_factor(Vec3(0, 0, 0), Vec3(0, 0, 1), big);
  EXPECT_GT(f, 0.9999);
  EXPECT_LE(f, 1.0);
}

// A cells × cells grid of two triangles per cell, vertex (i, j) at point(i, j),
// leaving out the cells `skip` names.
template <typename Point, typename Skip>
TriMesh grid_mesh(int cells, Point point, Skip skip) {
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> vh;
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) vh.push_back(mesh.add_vertex(point(i, j)));
  }
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      if (skip(i, j)) continue;
      const auto a = vh[j * (cells + 1) + i], b = vh[j * (cells + 1) + i + 1];
      const auto c = vh[(j + 1) * (cells + 1) + i + 1], d = vh[(j + 1) * (cells + 1) + i];
      mesh.add_face(a, b, c);
      mesh.add_face(a, c, d);
    }
  }
  return mesh;
}

std::vector<std::array<Vec3, 3>> root_triangles(const SurfaceHierarchy& h) {
  std::vector<std::array<Vec3, 3>> triangles;
  for (std::size_t f = 0; f < h.num_roots(); ++f) {
    const auto& c = h.corners(h.root(static_cast<int>(f)));
    triangles.push_back({h.point(c[0]), h.point(c[1]), h.point(c[2])});
  }
  return triangles;
}

// A cluster link integrates each shared edge once; every triangle's value
// must be what it gets alone, to the bit, wherever the receiver is: far, on
// the patch's vertices and edges, on a face's plane, with the patch half
// below its horizon.
TEST(FormFactor, SharedEdgesGiveEachTriangleItsOwnFormFactorExactly) {
  constexpr int kCells = 6;
  const SurfaceHierarchy h(grid_mesh(
      kCells, [](int i, int j) { return Vec3(i, j, 0.3 * std::sin(i) * std::cos(j)); }, [](int, int) { return false; }));
  const std::vector<std::array<Vec3, 3>> triangles = root_triangles(h);
  const auto edges = root_corner_edges(h);
  std::vector<std::pair<Vec3, Vec3>> receivers;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 x(3 + 5 * u(random), 3 + 5 * u(random), 2.0 * u(random) + 0.5);
    receivers.push_back({x, Vec3(u(random), u(random), -1.0).normalized()});
  }
  for (const auto& t : triangles) {
    receivers.push_back({t[0], Vec3(0.1, 0.2, 1).normalized()});                  // on a vertex
    receivers.push_back({0.5 * (t[0] + t[1]), Vec3(0, 0, 1)});                    // on an edge
    receivers.push_back({(t[0] + t[1] + t[2]) / 3.0 + Vec3(0, 0, 1e-3), Vec3(1, 0, 0)});  // patch across the horizon
  }
  const Vec3 approach(0.3, 0.1, 0.0);
  std::vector<double> shared;
  for (const auto& [x, n] : receivers) {
    shared_edge_form_factors(x, n, triangles, edges, &approach, shared);
    ASSERT_EQ(shared.size(), triangles.size());
    for (std::size_t j = 0; j < triangles.size(); ++j) {
      EXPECT_EQ(shared[j], point_triangle_form_factor(x, n, triangles[j], &approach)) << "triangle " << j;
    }
  }
}

// A planar cluster's form factor from its outline alone: on an 8 × 8 grid
// with a 2 × 2 hole, split into a small tree of clusters by hand, every
// cluster's outline is the edges of its roots that no other root of it has,
// and its contour integral is the sum of its triangles' own form factors
// wherever the outline says it can be taken; elsewhere it says so.
TEST(FormFactor, ClusterOutlineGivesTheSumOfItsTrianglesFormFactors) {
  constexpr int kCells = 8;
  const SurfaceHierarchy h(grid_mesh(
      kCells, [](int i, int j) { return Vec3(i + 0.1 * std::sin(3.0 * j), j, 0); },
      [](int i, int j) { return (i == 3 || i == 4) && (j == 3 || j == 4); }));  // the hole
  const std::vector<std::array<Vec3, 3>> triangles = root_triangles(h);
  // 0: everything; 1, 2: x below / above 4; 3, 4: cluster 1 split at y = 4.
  std::vector<RootCluster> clusters(5);
  clusters[0].first_child = 1;
  clusters[1].first_child = 3;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const Vec3 centroid = (triangles[f][0] + triangles[f][1] + triangles[f][2]) / 3.0;
    const auto root = static_cast<NodeId>(f);
    clusters[0].roots.push_back(root);
    clusters[centroid[0] < 4 ? 1 : 2].roots.push_back(root);
    if (centroid[0] < 4) clusters[centroid[1] < 4 ? 3 : 4].roots.push_back(root);
  }
  const auto edges = root_corner_edges(h);
  const ClusterOutlines outlines = cluster_outlines(h, clusters, edges, 1);
  const std::span<const Vec3> points(h.mesh().points(), h.mesh().n_vertices());
  std::mt19937 random(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    // The outline, edge by edge: in the cluster, one root runs along it.
    std::map<std::pair<VertexId, VertexId>, int> runs;  // directed edges of the cluster's roots
    for (NodeId r : clusters[c].roots) {
      const auto& k = h.corners(r);
      for (int e = 0; e < 3; ++e) ++runs[{k[e], k[(e + 1) % 3]}];
    }
    std::size_t expected = 0;
    for (const auto& [edge, count] : runs) expected += runs.count({edge.second, edge.first}) == 0 ? 1 : 0;
    const auto outline = outlines.of(c);
    EXPECT_EQ(outline.size(), expected) << "cluster " << c;
    for (const auto& e : outline) {
      EXPECT_EQ(runs.count({e[0], e[1]}), 1U) << "cluster " << c;
      EXPECT_EQ(runs.count({e[1], e[0]}), 0U) << "cluster " << c;
    }
    // Receivers whose horizon cuts the cluster (the outline clipped, as
    // each triangle is) as well as ones that see all of it.
    int taken = 0, clipped_ones = 0, refused = 0;
    for (int i = 0; i < 600; ++i) {
      const Vec3 x(4 + 6 * u(random), 4 + 6 * u(random), 3.0 * u(random));
      const Vec3 n = Vec3(u(random), u(random), -1.5 * u(random)).normalized();
      double sum = 0.0, lowest = 1e300;
      for (NodeId r : clusters[c].roots) sum += point_triangle_form_factor(x, n, triangles[r]);
      for (const auto& e : outline) lowest = std::min(lowest, OpenMesh::dot(n, points[e[0]] - x));
      bool clipped = true;
      const std::optional<double> f = outline_form_factor(x, n, Vec3(0, 0, 1), points, outline, &clipped);
      if (x[2] > 1e-3) {
        ASSERT_TRUE(f.has_value()) << "cluster " << c << " receiver " << i;
        EXPECT_NEAR(*f, sum, 1e-12 + 1e-10 * sum) << "cluster " << c << " receiver " << i;
        EXPECT_EQ(clipped, lowest < 0.0) << "cluster " << c << " receiver " << i;
        ++(lowest < 0.0 ? clipped_ones : taken);
      } else if (x[2] < 0.0) {
        EXPECT_FALSE(f.has_value()) << "cluster " << c << " receiver " << i;
        ++refused;
      }
    }
    EXPECT_GT(taken, 20) << "cluster " << c;
    EXPECT_GT(clipped_ones, 20) << "cluster " << c;
    EXPECT_GT(refused, 20) << "cluster " << c;
  }
}

// A bent surface (a cylinder's quarter, with a hole): where every triangle
// is seen plainly, its outline's contour integral is the sum of its
// triangles' form factors although they are not coplanar; where one is not
// (behind x, or cut by x's horizon), the outline is refused.
TEST(FormFactor, OpenOutlineOfABentSurfaceGivesTheSumOfItsTrianglesFormFactors) {
  constexpr int kCells = 8;
  const SurfaceHierarchy h(grid_mesh(
      kCells,
      [](int i, int j) {
        const double angle = 0.5 * M_PI * i / kCells;
        return Vec3(4.0 * std::sin(angle), j, 4.0 * (1.0 - std::cos(angle)));
      },
      [](int i, int j) { return i == 5 && j == 2; }));
  const std::vector<std::array<Vec3, 3>> triangles = root_triangles(h);
  std::vector<RootCluster> clusters(1);
  for (std::size_t f = 0; f < triangles.size(); ++f) clusters[0].roots.push_back(static_cast<NodeId>(f));
  const ClusterOutlines outlines = cluster_outlines(h, clusters, root_corner_edges(h), 1);
  const std::span<const Vec3> points(h.mesh().points(), h.mesh().n_vertices());
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int taken = 0, refused = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x(2.0 + 4.0 * u(random), 4.0 + 6.0 * u(random), 3.0 + 3.0 * u(random));
    const Vec3 n = Vec3(u(random), u(random), u(random)).normalized();
    double sum = 0.0;
    bool plain = true;
    for (const auto& t : triangles) {
      sum += point_triangle_form_factor(x, n, t);
      const Vec3 normal = OpenMesh::cross(t[1] - t[0], t[2] - t[0]).normalized();
      plain = plain && OpenMesh::dot(normal, x - t[0]) > 1e-3;
      for (const Vec3& p : t) plain = plain && OpenMesh::dot(n, p - x) > 1e-9;
    }
    const std::optional<double> f = open_outline_form_factor(x, n, triangles, points, outlines.of(0));
    if (plain) {
      ASSERT_TRUE(f.has_value()) << "receiver " << i;
      EXPECT_NEAR(*f, sum, 1e-12 + 1e-10 * sum) << "receiver " << i;
      ++taken;
    } else {
      if (f) {
        EXPECT_NEAR(*f, sum, 1e-12 + 1e-10 * sum) << "receiver " << i << ": an answer where one is not plain must agree";
      }
      refused += f ? 0 : 1;
    }
  }
  EXPECT_GT(taken, 50);
  EXPECT_GT(refused, 50);
}

TEST(Sampling, OneUniformSampleIsTheStratifiedPatternOfOne) {
  for (std::uint64_t key = 0; key < 1000; ++key) {
    const auto one = uniform_triangle_sample(sample_key(key, 2));
    const auto pattern = stratified_triangle_samples(1, sample_key(key, 2));
    ASSERT_EQ(pattern.size(), 1U);
    EXPECT_EQ(one.barycentric, pattern.front().barycentric);
  }
}

}  // namespace
}  // namespace lhr
