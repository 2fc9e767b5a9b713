// What holds for the classical method's constant elements alone: each leaf
// holds the closed form at its centre. The checks every method passes (the
// furnace, a receiver under an emitter, a closed box) are in
// tests/test_every_method.cpp.

#include <gtest/gtest.h>

#include <cmath>

#include "radiosity/classical_solver.hpp"
#include "radiosity/form_factor.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

TEST(ClassicalSolver, ReceiverUnderASquareEmitterMatchesTheFormFactor) {
  // Emitter with ρ = 0: the receiver's radiance is exactly ρ·Le·F(x), F the
  // point-to-square form factor, at every point (no interreflection back).
  const double rho = 0.6, le = 5.0, size = 0.5, height = 0.5;
  const Scene scene = test::emitter_over_receiver(size, height, rho, le);
  MeshingOptions meshing;
  meshing.max_edge = 0.25;
  MeshedScene model(scene, meshing);
  const int receiver = scene.materials[scene.surfaces[0].material].name == "receiver" ? 0 : 1;
  // The receiver refined five levels below its initial triangles, and
  // ε_BF = 1 keeping the solver from refining further, as in
  // EveryMethod/AnalyticScenes.ReceiverUnderASquareEmitterMatchesTheFormFactor.
  SurfaceHierarchy& h = model.hierarchy(receiver);
  for (int level = 0; level < 5; ++level) {
    for (NodeId leaf : h.leaves()) h.split(leaf);
  }
  ClassicalOptions options;
  options.eps_bf = 1.0;
  ClassicalSolver solver(model, options);
  solver.solve();
  const double lo = 0.5 - size / 2, hi = 0.5 + size / 2;
  const std::vector<Vec3> light{Vec3(lo, lo, height), Vec3(lo, hi, height), Vec3(hi, hi, height), Vec3(hi, lo, height)};
  const auto exact = [&](const Vec3& x) { return rho * le * point_polygon_form_factor(x, Vec3(0, 0, 1), light); };
  // Point collocation at element centres: every leaf holds ρ·Le·F(centre)
  // (nothing occludes, the emitter reflects nothing back).
  for (NodeId leaf : h.leaves()) {
    const double expected = exact(model.centroid(receiver, leaf));
    ASSERT_NEAR(solver.radiance(receiver, leaf)[0], expected, 1e-4 * expected) << "leaf " << leaf;
  }
  EXPECT_GT(h.num_leaves(), 10000u);
}

TEST(ClassicalSolver, ABlackReceiverGetsNoLinks) {
  // A closed cube of lights that reflect nothing: every value is its own
  // emission and there is nothing to link. Each black face used to take
  // links, and its uniform field was refined as if it could reflect them
  // (`lhr solve --method classical` of such a cube: 224 M links, 6 minutes).
  const Scene scene =
      test::closed_cube(test::grey_material("light", 0.0, 2.0), test::grey_material("top", 0.0, 3.0), "only lights");
  MeshingOptions meshing;
  meshing.max_edge = 0.5;
  MeshedScene model(scene, meshing);
  ClassicalSolver solver(model, ClassicalOptions{});
  solver.solve();
  EXPECT_EQ(solver.stats().links, 0u);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const double emitted = model.material(s).emission[0];
    for (NodeId leaf : model.hierarchy(s).leaves()) ASSERT_EQ(solver.radiance(s, leaf)[0], emitted);
  }
}


TEST(ClassicalSolver, WallsInACornerGetWhatTheirNeighbourShoots) {
  // Two walls meeting in a corner under a ceiling light. The exact answer on
  // the solver's own leaves: each leaf's radiance is the light's closed form
  // at its centre plus ρ Σ F(centre → leaf j) L_j over every leaf j of the
  // other wall. The walls are brighter near their common corner, where each
  // sees most of the other, so a link to the other wall as a whole, with its
  // mean, gave every leaf too little: about 5 % of what the walls exchange,
  // more as ε_BF shrank (docs/accuracy.md, "The classical method's
  // whole-surface links"). Each wall's mean must now be within 1.5 % of it.
  const double w = 4, h = 2.5, d = 4, size = 0.5, rho = 0.7, le = 10;
  PolygonSoup soup;
  soup.materials = {test::grey_material("wall", rho), test::grey_material("light", 0.0, le)};
  soup.groups = {"north", "east", "light"};
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(w, 0, 0), Vec3(w, h, 0), Vec3(0, h, 0), 0, 0);
  test::add_quad(soup, Vec3(w, 0, 0), Vec3(w, 0, d), Vec3(w, h, d), Vec3(w, h, 0), 0, 1);
  const double y = h - 1e-3, lo = w / 2 - size / 2, hi = w / 2 + size / 2;
  const std::vector<Vec3> light{Vec3(lo, y, lo), Vec3(hi, y, lo), Vec3(hi, y, hi), Vec3(lo, y, hi)};
  test::add_quad(soup, light[0], light[1], light[2], light[3], 1, 2);
  const Scene scene = test::scene_from_soup(soup, "corner");
  MeshingOptions meshing;
  meshing.max_edge = 1.0;
  MeshedScene model(scene, meshing);
  ClassicalOptions options;
  options.eps_bf = 3e-4;
  ClassicalSolver solver(model, options);
  solver.solve();
  std::vector<int> walls;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    if (model.material(s).name == "wall") walls.push_back(s);
  }
  ASSERT_EQ(walls.size(), 2u);
  for (int r : walls) {
    const int other = r == walls[0] ? walls[1] : walls[0];
    double area = 0, solved = 0, exchanged = 0, expected = 0;
    for (NodeId leaf : model.hierarchy(r).leaves()) {
      const Vec3 x = model.centroid(r, leaf), n = model.normal(r, leaf);
      double seen = 0;
      for (NodeId j : model.hierarchy(other).leaves()) {
        seen += point_triangle_form_factor(x, n, model.triangle(other, j)) * solver.radiance(other, j)[0];
      }
      const double a = model.area(r, leaf);
      area += a;
      solved += a * solver.radiance(r, leaf)[0];
      exchanged += a * rho * seen;
      expected += a * (rho * le * point_polygon_form_factor(x, n, light) + rho * seen);
    }
    EXPECT_NEAR(solved / area, expected / area, 0.015 * exchanged / area)
        << "wall " << r << ": exchanged " << exchanged / area << " of " << expected / area;
  }
}

TEST(ClassicalSolver, ASliverIsNotSplitBelowTheSceneFloorForPowerItCannotMove) {
  // A 1 × 10⁻⁴ strip standing on a lit floor. Its own floor, an eighth of
  // its width, allowed 80 000 elements along each row of it: the solve made
  // 526 000 elements and 45 M links in 76 s, all but 10 000 on the strip,
  // whose whole reflected power is 10⁻⁴ of the light's. Splits below the
  // scene's floor must now move eps_bf of the emitted power
  // (docs/accuracy.md, "Splits below the scene's floor"): 4 096 on the strip.
  const Scene scene = test::sliver_on_lit_floor();
  MeshingOptions meshing;
  meshing.max_edge = 0.25;
  MeshedScene model(scene, meshing);
  ClassicalSolver solver(model, ClassicalOptions{});
  solver.solve();
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const auto leaves = model.hierarchy(s).leaves();
    EXPECT_LT(leaves.size(), 20000u) << model.material(s).name;
    for (NodeId leaf : leaves) {
      const double l = solver.radiance(s, leaf)[0];
      ASSERT_TRUE(std::isfinite(l) && l >= 0.0 && l <= 1.0) << model.material(s).name << ": " << l;
    }
  }
}

}  // namespace
}  // namespace lhr
