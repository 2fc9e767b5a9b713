// Curved and skewed surfaces (docs/design.md §3: a non-planar polygon or a smooth
// tessellation is one curved surface): both methods solve them, a skewed quad
// lit by a light gets ρ·Le·F at its nodes, and a sphere in a lit box exports
// a valid mesh with finite, bounded values. The furnace inside a sphere, a
// closed curved surface lighting itself, runs for every method in
// tests/test_every_method.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "mesh/validate.hpp"
#include "radiosity/classical_solver.hpp"
#include "radiosity/form_factor.hpp"
#include "radiosity/linear_solver.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

Material grey(const std::string& name, double rho, double le = 0.0) {
  Material m;
  m.name = name;
  m.reflectance = Rgb(rho, rho, rho);
  m.emission = Rgb(le, le, le);
  return m;
}

TEST(CurvedSurfaces, InsideOfASphereIsOneCurvedSurface) {
  const Scene scene = test::furnace_sphere();
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_FALSE(scene.surfaces[0].planar);
}

// The published Cornell box's red wall (its bottom edge slants, its top
// edge does not: a warped quad) facing a square light of Kd 0.
Scene skewed_wall_and_light(double rho) {
  PolygonSoup soup;
  soup.materials = {grey("wall", rho), grey("light", 0.0, 1.0)};
  soup.groups = {"wall", "light"};
  test::add_quad(soup, Vec3(552.8, 0, 0), Vec3(549.6, 0, 559.2), Vec3(556, 548.8, 559.2), Vec3(556, 548.8, 0), 0, 0);
  // x = 300, facing +x (toward the wall).
  test::add_quad(soup, Vec3(300, 174, 180), Vec3(300, 374, 180), Vec3(300, 374, 380), Vec3(300, 174, 380), 1, 1);
  return test::scene_from_soup(soup, "skewed wall");
}

// A non-planar surface's best-fit normal: the Newell normal of its polygons.
Vec3 fit_normal(const Surface& s) {
  Vec3 n(0, 0, 0);
  for (const auto& polygon : s.polygons) {
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      n += OpenMesh::cross(s.points[polygon[k]], s.points[polygon[(k + 1) % polygon.size()]]);
    }
  }
  return n.normalized();
}

TEST(CurvedSurfaces, SkewedQuadUnderALightGetsTheFormFactorAtEveryNode) {
  // The wall's faces tilt by at most 0.4° from its best-fit plane, so
  // L(x) = ρ·Le·F(x) with F taken about that plane is right to well under
  // the 2 % allowed; the wall sees almost none of itself.
  const double rho = 0.5;
  const Scene scene = skewed_wall_and_light(rho);
  const int wall = scene.materials[scene.surfaces[0].material].name == "wall" ? 0 : 1;
  ASSERT_FALSE(scene.surfaces[wall].planar);
  const Surface& light = scene.surfaces[1 - wall];
  const Vec3 n = fit_normal(scene.surfaces[wall]);
  MeshingOptions meshing;
  meshing.max_edge = 140;
  {
    MeshedScene model(scene, meshing);
    LinearOptions options;
    LinearSolver solver(model, options);
    solver.solve();
    const SurfaceHierarchy& h = model.hierarchy(wall);
    for (VertexId v = 0; v < static_cast<VertexId>(h.num_vertices()); ++v) {
      const double exact = rho * point_polygon_form_factor(h.point(v), n, light.points);
      EXPECT_NEAR(solver.vertex_radiance(wall)[v][0], exact, 0.02 * exact + 1e-6) << "vertex " << v;
    }
  }
  {
    MeshedScene model(scene, meshing);
    ClassicalOptions options;
    ClassicalSolver solver(model, options);
    solver.solve();
    const SurfaceHierarchy& h = model.hierarchy(wall);
    for (NodeId leaf : h.leaves()) {
      const double exact = rho * point_polygon_form_factor(model.centroid(wall, leaf), n, light.points);
      EXPECT_NEAR(solver.radiance(wall, leaf)[0], exact, 0.02 * exact + 1e-6) << "leaf " << leaf;
    }
  }
}

// ∫|L − L_exact| dA over a solved surface, by a 10 × 10 barycentric rule per
// leaf on the linear interpolant of its vertex values, over ∫L_exact dA.
// exact(x, n) takes the point and its leaf's normal.
template <class Exact>
double roof_l1_error(const MeshedScene& model, int roof, const std::vector<Rgb>& radiance, const Exact& exact) {
  const SurfaceHierarchy& h = model.hierarchy(roof);
  constexpr int kSteps = 10;
  double error = 0.0, total = 0.0;
  for (NodeId leaf : h.leaves()) {
    const auto t = model.triangle(roof, leaf);
    const auto& k = h.corners(leaf);
    const Vec3 n = OpenMesh::cross(t[1] - t[0], t[2] - t[0]).normalized();
    const double area = 0.5 * OpenMesh::cross(t[1] - t[0], t[2] - t[0]).norm();
    const double weight = area / (kSteps * kSteps);
    for (int i = 0; i < kSteps; ++i) {
      for (int j = 0; i + j < kSteps; ++j) {
        // Centroids of the sub-triangles: kSteps² of equal area.
        for (int up = 0; up < (i + j + 1 < kSteps ? 2 : 1); ++up) {
          const double a = (i + (up ? 2.0 : 1.0) / 3.0) / kSteps, b = (j + (up ? 2.0 : 1.0) / 3.0) / kSteps;
          const Vec3 x = (1.0 - a - b) * t[0] + a * t[1] + b * t[2];
          const double solved = (1.0 - a - b) * radiance[k[0]][0] + a * radiance[k[1]][0] + b * radiance[k[2]][0];
          const double truth = exact(x, n);
          error += weight * std::abs(solved - truth);
          total += weight * truth;
        }
      }
    }
  }
  EXPECT_GT(total, 0.0);
  return total > 0.0 ? error / total : 0.0;
}

// Two unit facets meeting at the ridge x = 0, the first in z = 0 facing
// +z, the second bent down by 20° (one curved surface, material 0 "roof" of
// reflectance rho), and material 1 "light" (Kd 0, Le 1) for the caller's
// lamp.
PolygonSoup roof_soup(double rho) {
  const double bend = 20.0 * M_PI / 180.0, c = std::cos(bend), s = std::sin(bend);
  PolygonSoup soup;
  soup.materials = {grey("roof", rho), grey("light", 0.0, 1.0)};
  soup.groups = {"roof", "light"};
  soup.points = {{-1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {c, 0, -s}, {c, 1, -s}};
  soup.faces.push_back({{0, 1, 2, 3}, 0, 0, 0});
  soup.faces.push_back({{1, 4, 5, 2}, 0, 0, 0});
  return soup;
}

// A roof of two facets meeting at a ridge, bent down by 20° (one curved
// surface), and a light beside it that lies above the first facet's plane
// and below the second's: the radiance jumps from ρ·Le·F to 0 across the
// ridge. The node on the ridge holds the mean, and each leaf touching it a
// linear ramp (docs/accuracy.md, "Facet edges"), so what the solution
// misplaces goes with the size of those leaves, and with whether the mesh
// has the ridge as an edge at all. Truth: L = ρ·Le·F(x) on the lit facet,
// 0 on the other.
TEST(CurvedSurfaces, RadianceJumpingAtAFacetEdgeStaysAtTheEdge) {
  const double rho = 0.5;
  PolygonSoup soup = roof_soup(rho);
  test::add_quad(soup, Vec3(-2, 0, 0.1), Vec3(-2, 1, 0.1), Vec3(-2, 1, 0.5), Vec3(-2, 0, 0.5), 1, 1);
  const Scene scene = test::scene_from_soup(soup, "roof");
  const int roof = scene.materials[scene.surfaces[0].material].name == "roof" ? 0 : 1;
  ASSERT_FALSE(scene.surfaces[roof].planar);
  const Surface& light = scene.surfaces[1 - roof];
  const Vec3 lit_normal(0, 0, 1);
  const auto exact = [&](const Vec3& x, const Vec3& n) {
    return OpenMesh::dot(n, lit_normal) > 1.0 - 1e-9 ? rho * point_polygon_form_factor(x, n, light.points) : 0.0;
  };
  MeshingOptions meshing;
  meshing.max_edge = 0.25;
  MeshedScene model(scene, meshing);
  LinearSolver solver(model, LinearOptions{});
  solver.solve();
  const auto& radiance = solver.vertex_radiance(roof);
  const double error = roof_l1_error(model, roof, radiance, exact);
  std::cout << "relative L1 error " << error << "\n";
  // Measured: 0.34 %; 2.3 % when the initial mesh was remeshed across the
  // ridge (its triangles then straddled the horizon).
  EXPECT_LT(error, 0.01);
}

// The same roof under a large light far off to one side: each facet is lit
// almost evenly, at its own angle, so the radiance is nearly constant on
// each and halves across the ridge. Between nodes on both sides of the ridge
// the field is linear, so the paper's second difference sees nothing; only
// the facet-edge test (docs/accuracy.md, "Facet edges") narrows the ramps.
TEST(CurvedSurfaces, EvenlyLitFacetsAreRefinedTowardTheirRidge) {
  const double rho = 0.5;
  PolygonSoup soup = roof_soup(rho);
  // 8 × 8, 14 away at 45° above the first facet's side, facing the roof:
  // the first facet sees it at 45° from its normal, the second at 65°.
  const Vec3 centre(-10, 0.5, 10), along(std::sqrt(0.5) * 8.0, 0.0, std::sqrt(0.5) * 8.0), across(0, 8, 0);
  test::add_quad(soup, centre - 0.5 * along - 0.5 * across, centre - 0.5 * along + 0.5 * across,
                 centre + 0.5 * along + 0.5 * across, centre + 0.5 * along - 0.5 * across, 1, 1);
  const Scene scene = test::scene_from_soup(soup, "evenly lit roof");
  const int roof = scene.materials[scene.surfaces[0].material].name == "roof" ? 0 : 1;
  ASSERT_FALSE(scene.surfaces[roof].planar);
  const Surface& light = scene.surfaces[1 - roof];
  MeshingOptions meshing;
  meshing.max_edge = 0.25;
  MeshedScene model(scene, meshing);
  LinearSolver solver(model, LinearOptions{});
  solver.solve();
  const double error = roof_l1_error(model, roof, solver.vertex_radiance(roof), [&](const Vec3& x, const Vec3& n) {
    return rho * point_polygon_form_factor(x, n, light.points);
  });
  std::cout << "relative L1 error " << error << "\n";
  // Measured: 0.19 %; 1.8 % without the facet-edge test.
  EXPECT_LT(error, 0.006);
}

// A closed box of ρ = 0.7 with a light under its ceiling and an outward
// sphere in the middle.
Scene sphere_in_lit_box() {
  PolygonSoup soup;
  soup.materials = {grey("walls", 0.7), grey("sphere", 0.6), grey("light", 0.0, 10.0)};
  soup.groups = {"walls", "sphere", "light"};
  const Vec3 p000(0, 0, 0), p100(4, 0, 0), p010(0, 4, 0), p110(4, 4, 0);
  const Vec3 p001(0, 0, 4), p101(4, 0, 4), p011(0, 4, 4), p111(4, 4, 4);
  test::add_quad(soup, p000, p100, p110, p010, 0, 0);
  test::add_quad(soup, p001, p011, p111, p101, 0, 0);
  test::add_quad(soup, p000, p001, p101, p100, 0, 0);
  test::add_quad(soup, p010, p110, p111, p011, 0, 0);
  test::add_quad(soup, p000, p010, p011, p001, 0, 0);
  test::add_quad(soup, p100, p101, p111, p110, 0, 0);
  test::add_quad(soup, Vec3(1.5, 1.5, 3.99), Vec3(1.5, 2.5, 3.99), Vec3(2.5, 2.5, 3.99), Vec3(2.5, 1.5, 3.99), 2, 2);
  test::add_uv_sphere(soup, Vec3(2, 2, 1.5), 0.8, 24, 12, false, 1, 1);
  return test::scene_from_soup(soup, "sphere in a lit box");
}

void expect_sphere_solution(const MeshedScene& model, const std::vector<std::vector<Rgb>>& values,
                            const std::string& method) {
  // Every value is finite and bounded by what the light and the walls can
  // give (Le·ρ/(1 − ρ) with the largest ρ); the sphere's top, facing the
  // light, is brighter than its bottom, which sees only the floor.
  const double bound = 10.0 * 0.7 / (1.0 - 0.7);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const ConformingMesh mesh = model.hierarchy(s).conforming_mesh();
    EXPECT_TRUE(check_conforming_mesh(test::raw_mesh(mesh.mesh, values[s])).empty()) << method << ": surface " << s;
    for (const Rgb& v : values[s]) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(v[c])) << method;
        EXPECT_GE(v[c], 0.0) << method;
        EXPECT_LE(v[c], bound) << method;
      }
    }
  }
  int sphere = -1;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    if (model.scene().materials[model.scene().surfaces[s].material].name == "sphere") sphere = s;
  }
  ASSERT_GE(sphere, 0);
  const ConformingMesh mesh = model.hierarchy(sphere).conforming_mesh();
  double top = 0.0, bottom = 0.0;
  int top_n = 0, bottom_n = 0;
  for (const auto vh : mesh.mesh.vertices()) {
    const double z = mesh.mesh.point(vh)[2];
    if (z > 2.2) {
      top += values[sphere][vh.idx()][0];
      ++top_n;
    }
    if (z < 0.8) {
      bottom += values[sphere][vh.idx()][0];
      ++bottom_n;
    }
  }
  ASSERT_GT(top_n, 0);
  ASSERT_GT(bottom_n, 0);
  EXPECT_GT(top / top_n, 2.0 * bottom / bottom_n) << method;
}

TEST(CurvedSurfaces, SphereInALitBoxSolvesWithBothMethods) {
  const Scene scene = sphere_in_lit_box();
  MeshingOptions meshing;
  meshing.max_edge = 0.5;
  {
    MeshedScene model(scene, meshing);
    LinearOptions options;
    options.eps_link = 40.0;
    options.eps_pixel = 1.0;
    LinearSolver solver(model, options);
    solver.solve();
    std::vector<std::vector<Rgb>> values;
    for (int s = 0; s < model.num_surfaces(); ++s) {
      values.push_back(solver.vertex_radiance(s, model.hierarchy(s).conforming_mesh()));
    }
    expect_sphere_solution(model, values, "linear");
  }
  {
    MeshedScene model(scene, meshing);
    ClassicalOptions options;
    options.eps_bf = 0.01;
    ClassicalSolver solver(model, options);
    solver.solve();
    std::vector<std::vector<Rgb>> values;
    for (int s = 0; s < model.num_surfaces(); ++s) {
      values.push_back(solver.vertex_radiance(s, model.hierarchy(s).conforming_mesh()));
    }
    expect_sphere_solution(model, values, "classical");
  }
}

}  // namespace
}  // namespace lhr
