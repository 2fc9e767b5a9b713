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

}  // namespace
}  // namespace lhr
