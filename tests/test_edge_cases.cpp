// Numerical edge cases (issue "Stability and hostile input", docs/design.md §6): each
// has a bounded, finite, deterministic outcome with both methods.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "io/scene_loader.hpp"
#include "radiosity/classical_solver.hpp"
#include "radiosity/form_factor.hpp"
#include "radiosity/linear_solver.hpp"
#include "render/path_tracer.hpp"
#include "render/solution.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

Material make_material(const std::string& name, double rho, double emission) {
  Material m;
  m.name = name;
  m.reflectance = Rgb(rho, rho, rho);
  m.emission = Rgb(emission, emission, emission);
  return m;
}

// Every vertex value of every surface, by the linear method.
std::vector<Rgb> solve_linear(const Scene& scene, double h, LinearOptions options = {}, int* iterations = nullptr) {
  MeshingOptions meshing;
  meshing.max_edge = h;
  MeshedScene model(scene, meshing);
  LinearSolver solver(model, options);
  solver.solve();
  if (iterations) *iterations = solver.stats().iterations;
  std::vector<Rgb> all;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const auto& v = solver.vertex_radiance(s);
    all.insert(all.end(), v.begin(), v.end());
  }
  return all;
}

// Coarse ε_BF: these cases are about finite, bounded values, not accuracy.
std::vector<Rgb> solve_classical(const Scene& scene, double h, ClassicalOptions options = {.eps_bf = 0.02}) {
  MeshingOptions meshing;
  meshing.max_edge = h;
  MeshedScene model(scene, meshing);
  ClassicalSolver solver(model, options);
  solver.solve();
  std::vector<Rgb> all;
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const auto v = solver.vertex_radiance(s, model.hierarchy(s).conforming_mesh());
    all.insert(all.end(), v.begin(), v.end());
  }
  return all;
}

void expect_finite_non_negative(const std::vector<Rgb>& values, const std::string& what) {
  ASSERT_FALSE(values.empty()) << what;
  for (const Rgb& v : values) {
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(v[c]) && v[c] >= 0) << what << ": " << v[c];
  }
}

TEST(EdgeCases, NodesOnAShootersEdgeAndCornerStayFiniteAndBounded) {
  // Three mutually perpendicular unit squares meeting at the origin, two of
  // them emitting: the third's nodes on the shared edges and at the corner
  // lie in both shooters' planes.
  PolygonSoup soup;
  soup.materials = {make_material("floor", 0.5, 0), make_material("light", 0, 1)};
  soup.groups = {"floor", "wall_x", "wall_y"};
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), 0, 0);
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 1, 1), Vec3(0, 0, 1), 1, 1);  // x = 0, faces +x
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 0, 0), 1, 2);  // y = 0, faces +y
  const Scene scene = test::scene_from_soup(soup, "corner");
  for (const auto& values : {solve_linear(scene, 0.3), solve_classical(scene, 0.3)}) {
    expect_finite_non_negative(values, "corner");
    // Two walls can fill at most the whole projected hemisphere: L ≤ ρ·Le.
    for (const Rgb& v : values) EXPECT_LE(v[0], 1.0 + 1e-9);
  }
}

TEST(EdgeCases, CoplanarOverlappingFacesAreFinite) {
  // Two overlapping squares in the same plane (separate groups), lit from above.
  PolygonSoup soup;
  soup.materials = {make_material("a", 0.5, 0), make_material("light", 0, 1)};
  soup.groups = {"a", "b", "light"};
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), 0, 0);
  test::add_quad(soup, Vec3(0.5, 0.5, 0), Vec3(1.5, 0.5, 0), Vec3(1.5, 1.5, 0), Vec3(0.5, 1.5, 0), 0, 1);
  test::add_quad(soup, Vec3(0, 0, 1), Vec3(0, 1.5, 1), Vec3(1.5, 1.5, 1), Vec3(1.5, 0, 1), 1, 2);
  const Scene scene = test::scene_from_soup(soup, "coplanar");
  const auto a = solve_linear(scene, 0.3), b = solve_linear(scene, 0.3);
  expect_finite_non_negative(a, "coplanar, linear");
  expect_finite_non_negative(solve_classical(scene, 0.3), "coplanar, classical");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "deterministic";
}

TEST(EdgeCases, SliversAreFinite) {
  // A 1 × 1e-4 strip (aspect 1e4) standing on a lit floor.
  const Scene scene = test::sliver_on_lit_floor();
  expect_finite_non_negative(solve_linear(scene, 0.25), "sliver, linear");
  expect_finite_non_negative(solve_classical(scene, 0.25), "sliver, classical");
}

TEST(EdgeCases, AlmostWhiteFurnaceConverges) {
  // ρ = 0.99: L = Le/(1 − ρ) = 100, reached geometrically (0.99^n): measured
  // 1604 Jacobi iterations to a change below 1e-7 of Le, within 1 % of 100.
  const Scene scene = test::furnace_cube(0.99, 1.0);
  LinearOptions options;
  options.max_iterations = 3000;
  options.tolerance = 1e-7;
  options.eps_link = options.eps_pixel = 1e9;  // no refinement: this is about the iteration
  int iterations = 0;
  const auto values = solve_linear(scene, 1.0, options, &iterations);
  EXPECT_LT(iterations, 3000) << "converged before the limit";
  for (const Rgb& v : values) EXPECT_NEAR(v[0], 100.0, 1.0);
}

TEST(EdgeCases, WhiteFurnaceSolveWarnsThatItDidNotConverge) {
  const auto dir = test::fresh_dir("edge_white_furnace");
  test::write_text(dir / "white.mtl", "newmtl white\nKd 1 1 1\nKe 1 1 1\n");
  test::write_text(dir / "white.obj",
                   "mtllib white.mtl\nusemtl white\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
                   "v 1 1 1\nv 0 1 1\nf 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n");
  const auto r = test::run_lhr({"solve", (dir / "white.obj").string(), "--out", (dir / "out").string(),
                                "--max-iterations", "3", "--max-edge", "1", "--threads", "1"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("reflectance 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not converged after 3 iterations"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "stats.json"));
}

TEST(EdgeCases, LightsAMillionTimesApartStayFinite) {
  PolygonSoup soup;
  soup.materials = {make_material("walls", 0.5, 0), make_material("bright", 0, 1e6), make_material("dim", 0, 1)};
  soup.groups = {"walls", "bright", "dim"};
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), 0, 0);
  test::add_quad(soup, Vec3(0, 0, 1), Vec3(0, 0.4, 1), Vec3(0.4, 0.4, 1), Vec3(0.4, 0, 1), 1, 1);
  test::add_quad(soup, Vec3(0.6, 0.6, 1), Vec3(0.6, 1, 1), Vec3(1, 1, 1), Vec3(1, 0.6, 1), 2, 2);
  const Scene scene = test::scene_from_soup(soup, "dynamic range");
  expect_finite_non_negative(solve_linear(scene, 0.25), "1e6 range, linear");
  expect_finite_non_negative(solve_classical(scene, 0.25), "1e6 range, classical");
}

TEST(EdgeCases, OnlyEmittersGiveTheirEmission) {
  Scene scene = test::closed_cube(make_material("light", 0.0, 2.0), make_material("top", 0.0, 3.0), "only emitters");
  for (const auto& values : {solve_linear(scene, 0.5), solve_classical(scene, 0.5)}) {
    for (const Rgb& v : values) {
      ASSERT_TRUE(std::abs(v[0] - 2.0) < 1e-12 || std::abs(v[0] - 3.0) < 1e-12) << v[0];
    }
  }
}

TEST(EdgeCases, NoEmitterIsBlackWithAWarning) {
  const auto dir = test::fresh_dir("edge_no_emitter");
  test::write_text(dir / "dark.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nf 1 2 3 4\nf 1 5 6 2\n");
  for (const char* method : {"linear", "classical"}) {
    const auto r = test::run_lhr({"solve", (dir / "dark.obj").string(), "--out", (dir / method).string(),
                                  "--method", method});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("no emitter"), std::string::npos) << r.err;
    const std::string stats = test::read_text(dir / method / "stats.json");
    EXPECT_NE(stats.find("\"world_adaptation\""), std::string::npos);
  }
}

TEST(EdgeCases, TheSameSceneAtAnyScaleGivesTheSameImage) {
  // Radiance does not depend on units: the Cornell box at 1e-3 and 1e4 times
  // its size, camera scaled with it, gives the same picture.
  const LoadResult loaded = load_scene(test::source_dir() / "data/cornell/cornell.scene.json");
  const auto render = [&](double scale) {
    Scene scene = loaded.scene;
    for (Surface& s : scene.surfaces) {
      for (Vec3& p : s.points) p *= scale;
      s.area *= scale * scale;
    }
    SolveSettings settings;
    settings.camera = *scene.camera;
    settings.camera.eye *= scale;
    settings.camera.target *= scale;
    settings.camera.width = settings.camera.height = 96;
    settings.meshing.max_edge = 100.0 * scale;
    settings.linear.eps_link = 20;
    settings.linear.eps_pixel = 0.5;
    return solve_scene(scene, settings).view.radiance_image;
  };
  const Image small = render(1e-3), large = render(1e4);
  ASSERT_EQ(small.rgb.size(), large.rgb.size());
  double difference = 0.0, total = 0.0;
  for (std::size_t i = 0; i < small.rgb.size(); ++i) {
    difference += std::abs(small.rgb[i] - large.rgb[i]);
    total += std::abs(large.rgb[i]);
  }
  EXPECT_GT(total, 0.0);
  EXPECT_LT(difference / total, 0.01) << "mean relative difference of the radiance images";
}

}  // namespace
}  // namespace lhr

namespace lhr {
namespace {

TEST(EdgeCases, NonManifoldEdgeIsCutAndReported) {
  // Three faces on one edge (a floor with a fin above and below it) under a light.
  const auto dir = test::fresh_dir("edge_fin");
  test::write_text(dir / "fin.mtl", "newmtl white\nKd 0.5 0.5 0.5\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n");
  test::write_text(dir / "fin.obj",
                   "mtllib fin.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 0 0 -1\nv 1 0 -1\n"
                   "v 0 0 2\nv 0 1 2\nv 1 1 2\nv 1 0 2\n"
                   "usemtl white\nf 1 2 3 4\nf 1 5 6 2\nf 1 2 8 7\nusemtl light\nf 9 10 11 12\n");
  const LoadResult loaded = load_scene(dir / "fin.obj");
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("1 edges are shared by more than two faces"), std::string::npos)
      << loaded.warnings[0];
  EXPECT_EQ(loaded.scene.surfaces.size(), 4u) << "floor, upper fin, lower fin, light";
  expect_finite_non_negative(solve_linear(loaded.scene, 0.3), "fin, linear");
  const auto r = test::run_lhr({"solve", (dir / "fin.obj").string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("shared by more than two faces"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace lhr

namespace lhr {
namespace {

// Mixed scales: a 1 cm box resting on a 10 km floor under a 10 km light.
// A face is degenerate by its own shape, not by the scene's size, so the box
// is kept; its top sees only the light, so its radiance is ρ·Le·F exactly.
TEST(EdgeCases, ACentimetreBoxOnATenKilometreFloorIsKeptAndLitAsItsFormFactorSays) {
  constexpr double kRho = 0.5, kBox = 0.01, kFloor = 1e4, kHeight = 1e3;
  PolygonSoup soup;
  soup.materials = {test::grey_material("floor", kRho), test::grey_material("box", kRho),
                    test::grey_material("light", 0.0, 1.0)};
  soup.groups = {"floor", "box", "light"};
  const double f = 0.5 * kFloor, b = 0.5 * kBox;
  test::add_quad(soup, Vec3(-f, -f, 0), Vec3(f, -f, 0), Vec3(f, f, 0), Vec3(-f, f, 0), 0, 0);
  const std::array<Vec3, 4> light{Vec3(-f, -f, kHeight), Vec3(-f, f, kHeight), Vec3(f, f, kHeight),
                                  Vec3(f, -f, kHeight)};
  test::add_quad(soup, light[0], light[1], light[2], light[3], 2, 2);
  const Vec3 p000(-b, -b, 0), p100(b, -b, 0), p110(b, b, 0), p010(-b, b, 0);
  const Vec3 p001(-b, -b, kBox), p101(b, -b, kBox), p111(b, b, kBox), p011(-b, b, kBox);
  test::add_quad(soup, p001, p101, p111, p011, 1, 1);  // top, faces +z
  test::add_quad(soup, p000, p100, p101, p001, 1, 1);  // faces −y
  test::add_quad(soup, p100, p110, p111, p101, 1, 1);  // faces +x
  test::add_quad(soup, p110, p010, p011, p111, 1, 1);  // faces +y
  test::add_quad(soup, p010, p000, p001, p011, 1, 1);  // faces −x
  const SurfaceSplit split = split_into_surfaces(soup, 30.0);
  EXPECT_EQ(split.dropped_zero_area_faces, 0);
  ASSERT_EQ(split.surfaces.size(), 7u);
  Scene scene = test::scene_from_soup(soup, "mixed scales");

  int top = -1;
  for (int s = 0; s < static_cast<int>(scene.surfaces.size()); ++s) {
    if (scene.surfaces[s].material == 1 && scene.surfaces[s].normal[2] > 0.5) top = s;
  }
  ASSERT_GE(top, 0);
  MeshingOptions meshing;
  meshing.max_edge = 0.1 * kFloor;
  MeshedScene model(scene, meshing);
  LinearSolver solver(model, LinearOptions{});
  solver.solve();
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const std::vector<Rgb>& values = solver.vertex_radiance(s);
    expect_finite_non_negative(values, scene.surfaces[s].name);
    if (scene.surfaces[s].material == 2) continue;  // the light itself
    // Nothing reflects more than ρ times the light.
    for (const Rgb& v : values) EXPECT_LE(v[0], kRho * (1.0 + 1e-6)) << scene.surfaces[s].name;
  }
  const SurfaceHierarchy& h = model.hierarchy(top);
  const std::vector<Rgb>& top_values = solver.vertex_radiance(top);
  ASSERT_FALSE(top_values.empty());
  for (std::size_t v = 0; v < top_values.size(); ++v) {
    const Vec3 x = h.point(VertexId(static_cast<int>(v)));
    const double exact = kRho * point_polygon_form_factor(x, Vec3(0, 0, 1), light);
    EXPECT_NEAR(top_values[v][0], exact, 0.01 * exact) << "top vertex " << v;
  }
  expect_finite_non_negative(solve_classical(scene, 0.1 * kFloor), "classical");
}

}  // namespace
}  // namespace lhr

namespace lhr {
namespace {

// docs/design.md §3: only the front of a face reflects and emits. A camera
// outside a box whose faces all look inward sees only backs: black in the
// solution's view as in the path tracer's, and still pixels of the scene.
TEST(EdgeCases, ACameraOutsideAClosedBoxSeesBlackBacksAsThePathTracerDoes) {
  const Scene scene = test::closed_cube(test::grey_material("walls", 0.5), test::grey_material("top", 0.5, 1.0),
                                        "box seen from outside");
  Camera camera;
  camera.eye = Vec3(0.5, -2.5, 1.8);
  camera.target = Vec3(0.5, 0.5, 0.5);
  camera.up = Vec3(0, 0, 1);
  camera.width = camera.height = 48;
  SolveSettings settings;
  settings.camera = camera;
  settings.meshing.max_edge = 0.5;
  // Coarse: the view is on trial here, not the solution.
  settings.classical.eps_bf = 0.05;
  settings.linear.eps_link = 20;
  settings.linear.eps_pixel = 1;
  for (SolveMethod method : {SolveMethod::kLinear, SolveMethod::kClassical}) {
    settings.method = method;
    const Solution solution = solve_scene(scene, settings);
    const PathTracer tracer(scene);
    PathTraceOptions options;
    options.spp = 4;
    const ReferenceImage reference = tracer.render(camera, options);
    ASSERT_EQ(solution.view.hit_mask, reference.mask);
    int seen = 0;
    for (std::size_t i = 0; i < reference.mask.size(); ++i) {
      if (!reference.mask[i]) continue;
      ++seen;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(reference.radiance.rgb[3 * i + c], 0.0f) << "pixel " << i;
        ASSERT_EQ(solution.view.radiance_image.rgb[3 * i + c], 0.0f) << method_name(method) << ", pixel " << i;
      }
    }
    EXPECT_GT(seen, 48 * 48 / 8) << "the box fills much of the view";
  }
}

}  // namespace
}  // namespace lhr
