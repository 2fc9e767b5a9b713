// The receiver oracle's second difference (paper §4.1; docs/design.md §4,
// "Edge weights") on every pair of graph leaves a hierarchy produces:
// same-level pairs of irregular roots, regular pairs of their children, and
// coarse–fine pairs across T-vertices. A linear field is no reason to refine
// (ΔE = 0); a quadratic one shows its second difference. And in a solve, a
// graph left unjudged while nothing it reads moves (LinearOptions::oracle_drift)
// gives what judging every graph at every pass gives.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "io/scene_loader.hpp"
#include "mesh/hierarchy.hpp"
#include "radiosity/interaction_graph.hpp"
#include "radiosity/linear_solver.hpp"
#include "radiosity/receiver_oracle.hpp"
#include "radiosity/tone_map.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

// An affine image of the plane in space, its axes neither unit nor
// orthogonal: linear fields and parallelograms stay what they are.
Vec3 embed(double x, double y) {
  const Vec3 origin(0.4, -1.0, 2.0), u(0.9, 0.3, -0.4), v(0.2, 1.1, 0.5);
  return origin + x * u + y * v;
}

// Nine points of no pattern, triangulated into eight roots of different
// shapes (as a constrained Delaunay mesher leaves them).
SurfaceHierarchy irregular_patch() {
  const std::vector<std::array<double, 2>> xy = {{0, 0},     {3, 0.2},   {5.5, -0.5}, {0.3, 2.1}, {2.4, 2.8},
                                                 {4.9, 1.7}, {1.1, 4.6}, {3.7, 4.4},  {6, 4}};
  const std::vector<std::array<int, 3>> faces = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4},
                                                 {3, 4, 7}, {3, 7, 6}, {4, 5, 8}, {4, 8, 7}};
  TriMesh mesh;
  std::vector<TriMesh::VertexHandle> vh;
  for (const auto& p : xy) vh.push_back(mesh.add_vertex(embed(p[0], p[1])));
  for (auto f : faces) {
    const auto& a = xy[f[0]];
    const auto& b = xy[f[1]];
    const auto& c = xy[f[2]];
    if ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0) std::swap(f[1], f[2]);
    EXPECT_TRUE(mesh.add_face(vh[f[0]], vh[f[1]], vh[f[2]]).is_valid());
  }
  return SurfaceHierarchy(std::move(mesh));
}

// The patch's graph, its leaves split at random to levels 0..3.
struct MixedGraph {
  SurfaceHierarchy receiver = irregular_patch();
  InteractionGraph graph{0, 0, receiver};

  MixedGraph() {
    std::mt19937 random(7);
    std::vector<InteractionGraph::NewVertex> created;
    for (int i = 0; i < 40; ++i) {
      const auto& leaves = graph.leaves(receiver);
      const NodeId n = leaves[std::uniform_int_distribution<std::size_t>(0, leaves.size() - 1)(random)];
      if (receiver.level(n) < 3) graph.split(n, receiver, created);
    }
  }

  std::vector<OracleEdge> edges() const {
    std::vector<OracleEdge> out;
    for (NodeId leaf : graph.leaves(receiver)) oracle_edges(graph, receiver, leaf, out);
    return out;
  }
};

// Where line 3-4 crosses line 1-2, as parameters along each, found in the
// plane's own coordinates (embed's inverse is not needed: the crossing of
// two lines is affine-invariant, so any two coordinates of a projection that
// keeps the plane's points apart will do).
std::array<double, 2> crossing(const std::array<Vec3, 4>& p) {
  // Project onto the plane's (u, v) through the normal's dominant axis.
  const Vec3 n = OpenMesh::cross(p[1] - p[0], p[2] - p[0]);
  int drop = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(n[k]) > std::abs(n[drop])) drop = k;
  }
  const int i = (drop + 1) % 3, j = (drop + 2) % 3;
  // p1 + s (p2 − p1) = p3 + t (p4 − p3); α = 1 − s, β = 1 − t.
  const double ax = p[1][i] - p[0][i], ay = p[1][j] - p[0][j];
  const double bx = p[3][i] - p[2][i], by = p[3][j] - p[2][j];
  const double cx = p[2][i] - p[0][i], cy = p[2][j] - p[0][j];
  const double det = ax * (-by) - (-bx) * ay;
  const double s = (cx * (-by) - (-bx) * cy) / det;
  const double t = (ax * cy - ay * cx) / det;
  return {1.0 - s, 1.0 - t};
}

std::array<Vec3, 4> points(const SurfaceHierarchy& h, const OracleEdge& e) {
  return {h.point(e.vertex[0]), h.point(e.vertex[1]), h.point(e.vertex[2]), h.point(e.vertex[3])};
}

// ΔE of field f on edge e under a linear display (white at `white`, gamma 1).
template <typename F>
double display_error(const SurfaceHierarchy& h, const OracleEdge& e, F f, double white) {
  const LinearToneMap tone(white, 1.0);
  const ReceiverOracle oracle(tone, 0.05);
  const auto p = points(h, e);
  EdgeValues values;
  values.weights = edge_weights(p[0], p[1], p[2], p[3]);
  for (int i = 0; i < 4; ++i) values.own[i] = values.total[i] = f(p[i]);
  return oracle.display_error(values);
}

bool on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = OpenMesh::dot(p - a, ab) / ab.sqrnorm();
  return t > -1e-9 && t < 1 + 1e-9 && (a + t * ab - p).norm() < 1e-9 * ab.norm();
}

TEST(ReceiverOracle, EveryInnerEdgeOfEveryGraphLeafIsInExactlyOnePair) {
  const MixedGraph mixed;
  const SurfaceHierarchy& h = mixed.receiver;
  const auto edges = mixed.edges();
  std::size_t inner_edges = 0;
  for (NodeId leaf : mixed.graph.leaves(h)) {
    const auto& c = h.corners(leaf);
    for (int k = 0; k < 3; ++k) {
      if (h.is_boundary_edge(leaf, k)) continue;
      ++inner_edges;
      const Vec3 a = h.point(c[k]), b = h.point(c[(k + 1) % 3]);
      int pairs = 0;
      for (const OracleEdge& e : edges) {
        const Vec3 e1 = h.point(e.vertex[0]), e2 = h.point(e.vertex[1]);
        const bool as_left = e.left == leaf && on_segment(e1, a, b) && on_segment(e2, a, b);
        // The right side of a pair holds the edge or, if coarser, a half of it.
        const bool as_right = e.right == leaf && on_segment(e1, a, b) && on_segment(e2, a, b);
        pairs += as_left || as_right;
      }
      // A coarse leaf's edge is covered by its two fine neighbours' halves.
      const bool coarse_side = h.midpoint(c[k], c[(k + 1) % 3]) != kNoVertex &&
                               mixed.graph.index_of(h.midpoint(c[k], c[(k + 1) % 3])) >= 0;
      EXPECT_EQ(pairs, coarse_side ? 2 : 1) << "leaf " << leaf << " edge " << k;
    }
  }
  EXPECT_GT(inner_edges, 100U);
}

TEST(ReceiverOracle, ALinearFieldIsNoReasonToRefineOnAnyPair) {
  const MixedGraph mixed;
  const SurfaceHierarchy& h = mixed.receiver;
  const auto linear = [](const Vec3& p) { return 4.0 + 0.3 * p[0] - 0.7 * p[1] + 0.45 * p[2]; };
  const LinearToneMap tone(10.0, 1.0);
  int regular = 0, irregular = 0, coarse_fine = 0;
  // The paper's weights' ΔE over the field's display variation across the pair.
  double paper_irregular = 0.0, paper_coarse_fine = 0.0;
  for (const OracleEdge& e : mixed.edges()) {
    const auto p = points(h, e);
    EXPECT_LT(display_error(h, e, linear, 10.0), 1e-12) << "pair " << e.left << "-" << e.right;
    EdgeValues paper;
    for (int i = 0; i < 4; ++i) paper.own[i] = paper.total[i] = linear(p[i]);
    const auto [lo, hi] = std::minmax_element(paper.own.begin(), paper.own.end());
    const double relative = ReceiverOracle(tone, 0.05).display_error(paper) / ((*hi - *lo) / 10.0);
    if (h.level(e.left) != h.level(e.right)) {
      ++coarse_fine;
      paper_coarse_fine = std::max(paper_coarse_fine, relative);
    } else if ((p[0] + p[1] - p[2] - p[3]).norm() < 1e-9) {
      ++regular;
    } else {
      ++irregular;
      paper_irregular = std::max(paper_irregular, relative);
    }
  }
  // The paper's weights see this field as curved on both kinds of pair.
  EXPECT_GT(paper_irregular, 0.1);
  EXPECT_GT(paper_coarse_fine, 0.1);
  std::printf("paper weights, worst ΔE over the pair's variation: irregular %.3f, coarse-fine %.3f\n",
              paper_irregular, paper_coarse_fine);
  // The fixture has every kind of pair.
  EXPECT_GT(regular, 10);
  EXPECT_GT(irregular, 5);
  EXPECT_GT(coarse_fine, 5);
}

TEST(ReceiverOracle, AQuadraticFieldShowsItsSecondDifferenceOnEveryPair) {
  const MixedGraph mixed;
  const SurfaceHierarchy& h = mixed.receiver;
  const Vec3 m(0.6, -0.2, 0.3), n(0.1, 0.8, -0.5), centre(1.0, 1.0, 2.5);
  // f = 1 + Q(p − centre) + a linear part, Q(d) = (m·d)² + ½(n·d)².
  const auto form = [&](const Vec3& d) {
    return OpenMesh::dot(m, d) * OpenMesh::dot(m, d) + 0.5 * OpenMesh::dot(n, d) * OpenMesh::dot(n, d);
  };
  const auto quadratic = [&](const Vec3& p) { return 1.0 + form(p - centre) + 0.2 * p[1]; };
  constexpr double kWhite = 100.0;
  int checked = 0;
  for (const OracleEdge& e : mixed.edges()) {
    const auto p = points(h, e);
    // α f1 + (1−α) f2 − f(q) = α(1−α) Q(p1 − p2), and likewise along 3-4.
    const auto [alpha, beta] = crossing(p);
    const double expected =
        std::abs(alpha * (1 - alpha) * form(p[0] - p[1]) - beta * (1 - beta) * form(p[2] - p[3])) / kWhite;
    const double value = display_error(h, e, quadratic, kWhite);
    EXPECT_NEAR(value, expected, 1e-12 + 1e-9 * expected) << "pair " << e.left << "-" << e.right;
    if ((p[0] + p[1] - p[2] - p[3]).norm() < 1e-9) {
      // A regular pair: the paper's ½|f1 + f2 − f3 − f4|.
      const double paper =
          0.5 * std::abs(quadratic(p[0]) + quadratic(p[1]) - quadratic(p[2]) - quadratic(p[3])) / kWhite;
      EXPECT_NEAR(value, paper, 1e-12 + 1e-9 * paper);
    }
    EXPECT_GT(value, 0.0);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(ReceiverOracle, EdgeWeightsFallBackToThePapersWhereTheLinesDoNotCross) {
  // Lines 1-2 and 3-4 parallel: no crossing, the paper's weights.
  const auto parallel = edge_weights({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0});
  EXPECT_EQ(parallel, (std::array<double, 4>{1, 1, -1, -1}));
  // A square's diagonals: the paper's weights, exactly.
  const auto square = edge_weights({0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0});
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(square[i], i < 2 ? 1.0 : -1.0, 1e-15);
}

// The bound edge_refines decides most edges by must never say "no" where
// ΔE says "split": on random edges (random points, so irregular weights as
// well as the paper's; values over six decades; every visibility case), its
// verdict is refines(display_error) under both tone maps, at thresholds
// around each edge's own ΔE as well as far from it.
TEST(ReceiverOracle, TheBoundDecidesAsTheDisplayErrorDoes) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  ToneMapSettings settings;
  settings.world_adaptation = 0.05;
  const TumblinRushmeierToneMap tumblin(settings);
  const LinearToneMap linear(2.0, 2.2);
  int bounded = 0, cases = 0;
  for (const ToneMap* tone : {static_cast<const ToneMap*>(&tumblin), static_cast<const ToneMap*>(&linear)}) {
    const ReceiverOracle oracle(*tone, 0.1);
    for (int n = 0; n < 20000; ++n) {
      std::array<Vec3, 4> p;
      for (Vec3& q : p) q = Vec3(unit(rng), unit(rng), 0.1 * unit(rng));
      EdgeValues edge;
      edge.weights = n % 4 == 0 ? std::array<double, 4>{1, 1, -1, -1} : edge_weights(p[0], p[1], p[2], p[3]);
      const double scale = std::pow(10.0, -4.0 + 6.0 * unit(rng));
      for (int i = 0; i < 4; ++i) {
        edge.own[i] = n % 7 == 0 ? scale : scale * unit(rng);
        edge.total[i] = edge.own[i] + scale * unit(rng);
      }
      edge.visibility_1 = unit(rng);
      edge.visibility_2 = n % 2 == 0 ? edge.visibility_1 : unit(rng);
      const double error = oracle.display_error(edge);
      for (double pixels : {0.5, 20.0, 3000.0}) {
        for (double eps : {error * pixels, error * pixels * (1 + 1e-12), error * pixels * 0.5, 0.3, 1e-6}) {
          if (!(eps > 0)) continue;
          ++cases;
          const bool exact = ReceiverOracle::refines(error, pixels, eps);
          ASSERT_EQ(oracle.edge_refines(edge, pixels, eps), exact) << "n " << n << ", pixels " << pixels << ", eps " << eps;
          if (!exact) ++bounded;
        }
      }
    }
  }
  EXPECT_GT(bounded, cases / 10) << "the cases must include edges below the threshold";
}

// docs/design.md, "One iteration": a graph is judged again, by either
// oracle, only when its links, the hierarchy the oracle reads, or (by
// oracle_drift, summed) the radiance, importance and adaptation it reads
// have moved. The truth is the same solve
// judging every graph at every pass (oracle_drift 0): the links and each
// surface's mean radiance must agree, while fewer graphs are judged. (Here
// late verdicts hardly depend on the inputs' last per cent: leaving the
// radiance's drift out altogether moved the links by 0.04 %.)
TEST(ReceiverOracle, GraphsLeftUnjudgedWhileNothingMovesGiveWhatJudgingEveryGraphGives) {
  const LoadResult loaded = load_scene(test::source_dir() / "data/cornell/cornell.scene.json");
  struct Outcome {
    std::vector<double> mean;  // per surface, over its vertices
    std::size_t links, judgements, shooter_judgements, splits;
    int iterations;
  };
  const auto run = [&](double drift) {
    MeshingOptions meshing;
    meshing.max_edge = 120.0;
    MeshedScene model(loaded.scene, meshing);
    LinearOptions options = test::quick_linear_options(model, 20.0, 0.3, 96);
    options.oracle_drift = drift;
    LinearSolver solver(model, options);
    Outcome out{{}, 0, 0, 0, 0, 0};
    solver.solve([&](int iteration, double) { out.iterations = iteration; });
    for (int s = 0; s < model.num_surfaces(); ++s) {
      double sum = 0.0;
      for (const Rgb& v : solver.vertex_radiance(s)) sum += luminance(v);
      out.mean.push_back(sum / static_cast<double>(solver.vertex_radiance(s).size()));
    }
    out.links = solver.stats().links;
    out.judgements = solver.stats().receiver_judgements;
    out.shooter_judgements = solver.stats().shooter_judgements;
    out.splits = solver.stats().receiver_splits;
    return out;
  };
  const Outcome every = run(0.0), moved = run(LinearOptions{}.oracle_drift);
  ASSERT_GT(every.splits, 10u) << "the receiver oracle must refine";
  ASSERT_GE(every.iterations, 4);
  EXPECT_LT(moved.judgements, every.judgements);
  EXPECT_LT(moved.shooter_judgements, every.shooter_judgements) << "the shooter oracle watches its graphs too";
  EXPECT_NEAR(static_cast<double>(moved.links), static_cast<double>(every.links), 0.01 * every.links);
  EXPECT_NEAR(static_cast<double>(moved.splits), static_cast<double>(every.splits), 0.01 * every.splits);
  ASSERT_EQ(moved.mean.size(), every.mean.size());
  for (std::size_t s = 0; s < every.mean.size(); ++s) {
    EXPECT_NEAR(moved.mean[s], every.mean[s], 0.005 * every.mean[s]) << loaded.scene.surfaces[s].name;
  }
  std::printf("receiver oracle judged %zu of %zu graphs, shooter oracle %zu of %zu; links %zu / %zu; splits %zu / %zu; "
              "iterations %d / %d\n",
              moved.judgements, every.judgements, moved.shooter_judgements, every.shooter_judgements, moved.links,
              every.links, moved.splits, every.splits, moved.iterations, every.iterations);
}

}  // namespace
}  // namespace lhr
