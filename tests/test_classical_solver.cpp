// Classical hierarchical radiosity against closed forms: the furnace and a
// two-surface exchange.

#include <gtest/gtest.h>

#include <cmath>

#include "radiosity/classical_solver.hpp"
#include "radiosity/form_factor.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

TEST(ClassicalSolver, FurnaceReachesEOverOneMinusRho) {
  // Closed cube, ρ = 0.5, Le = 1: L = Le/(1−ρ) = 2 everywhere.
  const Scene scene = test::furnace_cube(0.5, 1.0);
  MeshingOptions meshing;
  meshing.max_edge = 0.7;
  SceneModel model(scene, meshing);
  ClassicalOptions options;
  // Every surface emits, so links at the corners refine down to the minimum
  // element size: leaves at several levels meet there.
  options.eps_bf = 0.2;
  options.tolerance = 1e-7;
  ClassicalSolver solver(model, options);
  solver.solve();
  ASSERT_EQ(model.num_surfaces(), 6);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const ConformingMesh mesh = model.hierarchy(s).conforming_mesh();
    const auto values = solver.vertex_radiance(s, mesh);
    for (const Rgb& v : values) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], 2.0, 0.02) << "surface " << s;
    }
  }
  int max_level = 0;
  for (int s = 0; s < model.num_surfaces(); ++s) max_level = std::max(max_level, model.hierarchy(s).max_level());
  EXPECT_GE(max_level, 3) << "the test must exercise refinement";
}

TEST(ClassicalSolver, ReceiverUnderASquareEmitterMatchesTheFormFactor) {
  // Emitter with ρ = 0: the receiver's radiance is exactly ρ·Le·F(x), F the
  // point-to-square form factor, at every point (no interreflection back).
  const double rho = 0.6, le = 5.0, size = 0.5, height = 0.5;
  const Scene scene = test::emitter_over_receiver(size, height, rho, le);
  MeshingOptions meshing;
  meshing.max_edge = 0.25;
  SceneModel model(scene, meshing);
  ClassicalOptions options;
  options.eps_bf = 1e-3;
  ClassicalSolver solver(model, options);
  solver.solve();
  const int receiver = scene.materials[scene.surfaces[0].material].name == "receiver" ? 0 : 1;
  const double lo = 0.5 - size / 2, hi = 0.5 + size / 2;
  const std::vector<Vec3> light{Vec3(lo, lo, height), Vec3(lo, hi, height), Vec3(hi, hi, height), Vec3(hi, lo, height)};
  // Point collocation at element centres: every leaf holds ρ·Le·F(centre)
  // (nothing occludes, the emitter reflects nothing back).
  const SurfaceHierarchy& h = model.hierarchy(receiver);
  for (NodeId leaf : h.leaves()) {
    const double exact = rho * le * point_polygon_form_factor(model.centroid(receiver, leaf), Vec3(0, 0, 1), light);
    EXPECT_NEAR(solver.radiance(receiver, leaf)[0], exact, 1e-4 * exact) << "leaf " << leaf;
  }
  // Vertex values average the leaves around a vertex (constant elements have
  // none of their own): each lies between the smallest and largest exact
  // centre value of the leaves it touches.
  const ConformingMesh mesh = h.conforming_mesh();
  const auto values = solver.vertex_radiance(receiver, mesh);
  std::vector<double> lowest(mesh.mesh.n_vertices(), 1e300), highest(mesh.mesh.n_vertices(), -1e300);
  for (const auto fh : mesh.mesh.faces()) {
    const double exact = rho * le * point_polygon_form_factor(model.centroid(receiver, mesh.leaf[fh.idx()]),
                                                              Vec3(0, 0, 1), light);
    for (const auto vh : mesh.mesh.fv_range(fh)) {
      lowest[vh.idx()] = std::min(lowest[vh.idx()], exact);
      highest[vh.idx()] = std::max(highest[vh.idx()], exact);
    }
  }
  int checked = 0;
  for (const auto vh : mesh.mesh.vertices()) {
    EXPECT_GE(values[vh.idx()][0], lowest[vh.idx()] * (1 - 1e-4));
    EXPECT_LE(values[vh.idx()][0], highest[vh.idx()] * (1 + 1e-4));
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

}  // namespace
}  // namespace lhr
