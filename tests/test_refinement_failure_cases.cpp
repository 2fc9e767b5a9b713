// The failure cases of paper fig. 6, where a refinement criterion on vertex
// values alone goes wrong, and what lhr does about each (docs/design.md §6):
//  (a) two shooters whose slope changes across an edge cancel in the sum:
//      the oracle runs per shooter (interaction graph), not on the sum;
//  (b) a shadow boundary crossing an edge whose vertices have equal values:
//      the visibility difference makes the oracle conservative;
//  (c) a shadow smaller than the initial mesh inside one patch: no vertex
//      sees it, so no oracle can; the minimum density h resolves it.

#include <gtest/gtest.h>

#include <cmath>

#include "radiosity/form_factor.hpp"
#include "radiosity/linear_solver.hpp"
#include "radiosity/receiver_oracle.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

// A square light of side `size` at height `height` centred over (cx, cy),
// facing down (counter-clockwise seen from below).
std::vector<Vec3> light_square(double cx, double cy, double size, double height) {
  const double h = size / 2;
  return {Vec3(cx - h, cy - h, height), Vec3(cx - h, cy + h, height), Vec3(cx + h, cy + h, height),
          Vec3(cx + h, cy - h, height)};
}

TEST(RefinementFailureCases, CancellingShootersAreCaughtPerShooterNotOnTheSum) {
  // Receiver edge from v1 = (0,−s) to v2 = (0,s) on a floor facing up;
  // opposite vertices v3 = (−h,0), v4 = (h,0). Shooter A is a light right
  // above the edge (its contribution peaks there: concave across the edge);
  // shooter B is off to the side, on the convex tail of its own peak, with an
  // emission chosen so that the two second differences cancel exactly.
  const double s = 0.05, h = 0.1, rho = 0.5;
  const std::array<Vec3, 4> v{Vec3(0, -s, 0), Vec3(0, s, 0), Vec3(-h, 0, 0), Vec3(h, 0, 0)};
  const Vec3 up(0, 0, 1);
  const auto light_a = light_square(0.0, 0.0, 0.1, 0.3);
  const auto light_b = light_square(0.6, 0.0, 0.1, 0.3);
  std::array<double, 4> fa{}, fb{};
  for (int i = 0; i < 4; ++i) {
    fa[i] = point_polygon_form_factor(v[i], up, light_a);
    fb[i] = point_polygon_form_factor(v[i], up, light_b);
  }
  const double curvature_a = fa[0] + fa[1] - fa[2] - fa[3];
  const double curvature_b = fb[0] + fb[1] - fb[2] - fb[3];
  ASSERT_GT(curvature_a, 0) << "A peaks on the edge";
  ASSERT_LT(curvature_b, 0) << "B is convex there";
  const double le_a = 1.0, le_b = -le_a * curvature_a / curvature_b;

  EdgeValues shooter_a, shooter_b, summed;
  for (int i = 0; i < 4; ++i) {
    shooter_a.own[i] = rho * le_a * fa[i];
    shooter_b.own[i] = rho * le_b * fb[i];
    summed.total[i] = shooter_a.own[i] + shooter_b.own[i];
  }
  shooter_a.total = shooter_b.total = summed.total;
  summed.own = summed.total;  // one "shooter" standing for all: a test on the summed radiosity
  const LinearToneMap tone(*std::max_element(summed.total.begin(), summed.total.end()), 1.0);
  const ReceiverOracle oracle(tone, 0.1);
  const double error_a = oracle.display_error(shooter_a);
  const double error_b = oracle.display_error(shooter_b);
  const double error_sum = oracle.display_error(summed);
  EXPECT_GT(error_a, 0.02) << "A alone changes slope across the edge";
  EXPECT_NEAR(error_b, error_a, 1e-9) << "B's opposite slope change has the same size";
  EXPECT_LT(error_sum, 1e-9) << "the sum is linear across the edge";
  // With ε_pixel = 1 over 100 pixels the per-shooter oracle splits, the summed one would not.
  EXPECT_TRUE(ReceiverOracle::refines(error_a, 100.0, 1.0));
  EXPECT_FALSE(ReceiverOracle::refines(error_sum, 100.0, 1.0));
}

TEST(RefinementFailureCases, ShadowBoundaryWithEqualEdgeValuesIsCaughtByVisibility) {
  // The edge's vertices have equal values although a shadow boundary crosses
  // the edge (v2 is nearer the light but half hidden), and the values vary
  // linearly across it: the second difference sees nothing.
  EdgeValues edge;
  edge.own = {0.5, 0.5, 0.8, 0.2};
  edge.total = edge.own;
  edge.visibility_1 = 1.0;
  edge.visibility_2 = 0.5;
  const LinearToneMap tone(1.0, 1.0);
  const double with_visibility = ReceiverOracle(tone, 0.1).display_error(edge);
  const double values_only = ReceiverOracle(tone, 2.0).display_error(edge);  // threshold never reached
  EXPECT_NEAR(values_only, 0.0, 1e-12);
  EXPECT_NEAR(with_visibility, 0.8 - 0.2, 1e-12) << "conservative: the range of the four values";
  // Below the visibility threshold the second difference is used.
  edge.visibility_2 = 0.95;
  EXPECT_NEAR(ReceiverOracle(tone, 0.1).display_error(edge), 0.0, 1e-12);
}

// A unit floor (ρ 0.5) under a 0.6 × 0.6 light at height 1, with a small
// black occluder of side `blocker` hovering just above the floor.
Scene floor_with_small_shadow(double blocker, const Vec3& centre) {
  PolygonSoup soup;
  Material floor_material, light_material, blocker_material;
  floor_material.name = "floor";
  floor_material.reflectance = Rgb(0.5, 0.5, 0.5);
  light_material.name = "light";
  light_material.reflectance = Rgb(0, 0, 0);
  light_material.emission = Rgb(1, 1, 1);
  blocker_material.name = "blocker";
  blocker_material.reflectance = Rgb(0, 0, 0);
  soup.materials = {floor_material, light_material, blocker_material};
  soup.groups = {"floor", "light", "blocker"};
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), 0, 0);
  const auto l = light_square(0.5, 0.5, 0.6, 1.0);
  test::add_quad(soup, l[0], l[1], l[2], l[3], 1, 1);
  const auto b = light_square(centre[0], centre[1], blocker, centre[2]);
  test::add_quad(soup, b[0], b[1], b[2], b[3], 2, 2);
  return test::scene_from_soup(soup, "floor with a small shadow");
}

TEST(RefinementFailureCases, SmallShadowInsideOnePatchNeedsTheMinimumDensity) {
  const double blocker = 0.06;
  const Vec3 centre(0.31, 0.37, 0.02);
  const Scene scene = floor_with_small_shadow(blocker, centre);
  const auto solve = [&](double h, double& worst_ratio, bool& vertex_in_shadow) {
    MeshingOptions meshing;
    meshing.max_edge = h;
    MeshedScene model(scene, meshing);
    LinearOptions options;
    // A threshold at which the light's smooth gradient needs no refinement,
    // so only the initial mesh can meet the shadow.
    options.eps_pixel = 50.0;
    options.eps_link = 5.0;
    LinearSolver solver(model, options);
    solver.solve();
    int floor = 0;
    while (model.material(floor).emission[0] > 0 || model.material(floor).reflectance[0] == 0) ++floor;
    const SurfaceHierarchy& hierarchy = model.hierarchy(floor);
    const auto light = light_square(0.5, 0.5, 0.6, 1.0);
    worst_ratio = 1e300;
    vertex_in_shadow = false;
    for (VertexId v = 0; v < static_cast<VertexId>(hierarchy.num_vertices()); ++v) {
      const Vec3 x = hierarchy.point(v);
      const double unoccluded = 0.5 * point_polygon_form_factor(x, Vec3(0, 0, 1), light);
      worst_ratio = std::min(worst_ratio, solver.vertex_radiance(floor)[v][0] / unoccluded);
      if (hierarchy.vertex_level(v) == 0 && std::abs(x[0] - centre[0]) < blocker / 2 &&
          std::abs(x[1] - centre[1]) < blocker / 2) {
        vertex_in_shadow = true;
      }
    }
  };
  double coarse_ratio = 0, fine_ratio = 0;
  bool coarse_vertex_inside = true, fine_vertex_inside = false;
  solve(0.5, coarse_ratio, coarse_vertex_inside);
  ASSERT_FALSE(coarse_vertex_inside) << "precondition: the shadow lies inside one initial patch";
  EXPECT_GT(coarse_ratio, 0.97) << "h above the shadow's size: every vertex sees the whole light, the shadow is missed";
  solve(0.03, fine_ratio, fine_vertex_inside);
  EXPECT_TRUE(fine_vertex_inside) << "h below the shadow's size puts initial vertices in it";
  EXPECT_LT(fine_ratio, 0.2) << "and the shadow is resolved";
}

}  // namespace
}  // namespace lhr
