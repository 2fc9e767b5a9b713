// Energy balance: what the lights emit is absorbed by the walls or leaves
// through an opening. On the Cornell box the escaping part is computed
// independently of the solver's own links (form factors to the opening and
// kernel-weighted visibility); closed rooms let nothing escape (a closed box
// for every method: tests/test_every_method.cpp).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "io/scene_loader.hpp"
#include "radiosity/classical_solver.hpp"
#include "radiosity/form_factor.hpp"
#include "radiosity/sampling.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

// The open front of the box (z = 0), counter-clockwise seen from inside.
const std::array<Vec3, 4> kOpening{Vec3(0, 0, 0), Vec3(552.8, 0, 0), Vec3(556, 548.8, 0), Vec3(0, 548.8, 0)};

// Share of a leaf's outgoing power (constant radiance) that leaves through
// the opening: the mean over points x of the leaf of F(x, opening) times
// the visible share of the opening, each visibility sample weighted by the
// point-to-point kernel cosθx cosθy / r². The unweighted share of rays
// from the leaf's centre used before counted points of the opening behind
// the leaf's own plane (seen from a block's top) as hidden and weighed
// grazing directions like frontal ones: it put the escape 5 % low.
double escaping_share(const RayCaster& rays, const std::array<Vec3, 3>& leaf, const Vec3& n, std::uint64_t key) {
  const Vec3 inward(0, 0, 1);
  const std::array<std::array<Vec3, 3>, 2> halves{{{kOpening[0], kOpening[1], kOpening[2]},
                                                   {kOpening[0], kOpening[2], kOpening[3]}}};
  const auto points = stratified_triangle_samples(3, sample_key(key, 1));
  double sum = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 x = at(leaf, points[i]);
    const double f = point_polygon_form_factor(x, n, kOpening);
    if (!(f > 0)) continue;
    std::vector<ShadowRay> segments;
    std::vector<double> weights;
    for (std::size_t t = 0; t < halves.size(); ++t) {
      for (const TriangleSample& ts : stratified_triangle_samples(4, sample_key(key, 2 + i, t))) {
        const Vec3 y = at(halves[t], ts);
        const Vec3 d = y - x;
        const double w = std::max(0.0, OpenMesh::dot(n, d)) * std::max(0.0, -OpenMesh::dot(inward, d)) /
                         (d.sqrnorm() * d.sqrnorm());
        if (!(w > 0)) continue;
        segments.push_back({rays.lift(x, n), rays.lift(y, inward)});
        weights.push_back(w);
      }
    }
    double total = 0.0, clear = 0.0;
    if (!segments.empty()) {
      std::vector<std::uint8_t> blocked(segments.size());
      rays.occluded(segments, blocked);
      for (std::size_t k = 0; k < segments.size(); ++k) {
        total += weights[k];
        clear += blocked[k] ? 0.0 : weights[k];
      }
    }
    sum += f * (total > 0 ? clear / total : 1.0);
  }
  return sum / static_cast<double>(points.size());
}

// Measured (absorbed + escaped over emitted, R/G/B) at h = 100, ε_BF = 0.01:
// 99.59 / 99.68 / 99.95 %. Before root clusters shot over their exposed
// area only (see radiosity/classical_solver.hpp), 96.9 / 97.2 / 98.0 %: the
// floor under the blocks and the ceiling above the lamp, dark and seen by
// nobody, dimmed the whole-surface shooters; the earlier unweighted escape
// estimate put that at 95.7 %.
// At finer ε_BF the balance drifts down (ε 0.003: 98.8–99.2 %, ε 0.001:
// 97.3–98.1 %) while the unweighted column sums (Σ A_i F_ij over receivers
// i against shooter j's area times its share of directions that reach a
// surface) stay within 1 %: links from coarse shooters carry their mean
// radiance, and the more the receivers are refined the sharper the shadows
// on those shooters; the BF test bounds each link's transfer, not that
// correlation. This test runs at the coarse ε 0.01, where that error is
// smallest, so that a leak in the transport itself (as above) stands out.
TEST(EnergyBalance, CornellBoxEmittedEqualsAbsorbedPlusEscaped) {
  const LoadResult loaded = load_scene(test::source_dir() / "data/cornell/cornell.scene.json");
  MeshingOptions meshing;
  meshing.max_edge = 100.0;
  MeshedScene model(loaded.scene, meshing);
  ClassicalOptions options;
  options.eps_bf = 0.01;
  options.tolerance = 1e-7;
  ClassicalSolver solver(model, options);
  solver.solve();

  Rgb emitted(0, 0, 0), absorbed(0, 0, 0), escaped(0, 0, 0);
  for (int s = 0; s < model.num_surfaces(); ++s) {
    const Material& m = model.material(s);
    for (NodeId leaf : model.hierarchy(s).leaves()) {
      const double a = model.area(s, leaf);
      const double share =
          escaping_share(model.rays(), model.triangle(s, leaf), model.normal(s, leaf), sample_key(s, leaf));
      for (int c = 0; c < 3; ++c) {
        emitted[c] += M_PI * a * m.emission[c];
        absorbed[c] += M_PI * a * (1.0 - m.reflectance[c]) * solver.gathered(s, leaf)[c];
        escaped[c] += M_PI * a * solver.radiance(s, leaf)[c] * share;
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(escaped[c], 0.05 * emitted[c]) << "the open front lets light out";
    EXPECT_NEAR(absorbed[c] + escaped[c], emitted[c], 0.01 * emitted[c])
        << "channel " << c << ": absorbed " << absorbed[c] << ", escaped " << escaped[c];
  }
}

}  // namespace
}  // namespace lhr

namespace lhr {
namespace {

// A closed 5 × 4 room, 2.8 high, every surface ρ = 0.8, with a 0.4 × 0.4
// lamp (ρ 0.8 too, so that what reaches it is accounted for) hanging 1 cm
// under the ceiling. The walls face into the room.
Scene bright_closed_room() {
  constexpr double kX = 5.0, kY = 2.8, kZ = 4.0, kHalf = 0.2, kLampY = kY - 0.01;
  PolygonSoup soup;
  soup.materials = {test::grey_material("wall", 0.8), test::grey_material("lamp", 0.8, 10.0)};
  soup.groups = {"floor", "ceiling", "wall_z0", "wall_z1", "wall_x0", "wall_x1", "lamp"};
  test::add_quad(soup, Vec3(0, 0, kZ), Vec3(kX, 0, kZ), Vec3(kX, 0, 0), Vec3(0, 0, 0), 0, 0);
  test::add_quad(soup, Vec3(kX, kY, 0), Vec3(kX, kY, kZ), Vec3(0, kY, kZ), Vec3(0, kY, 0), 0, 1);
  test::add_quad(soup, Vec3(kX, 0, 0), Vec3(kX, kY, 0), Vec3(0, kY, 0), Vec3(0, 0, 0), 0, 2);
  test::add_quad(soup, Vec3(0, kY, kZ), Vec3(kX, kY, kZ), Vec3(kX, 0, kZ), Vec3(0, 0, kZ), 0, 3);
  test::add_quad(soup, Vec3(0, kY, 0), Vec3(0, kY, kZ), Vec3(0, 0, kZ), Vec3(0, 0, 0), 0, 4);
  test::add_quad(soup, Vec3(kX, 0, kZ), Vec3(kX, kY, kZ), Vec3(kX, kY, 0), Vec3(kX, 0, 0), 0, 5);
  const double cx = 0.5 * kX, cz = 0.5 * kZ;
  test::add_quad(soup, Vec3(cx - kHalf, kLampY, cz - kHalf), Vec3(cx + kHalf, kLampY, cz - kHalf),
                 Vec3(cx + kHalf, kLampY, cz + kHalf), Vec3(cx - kHalf, kLampY, cz + kHalf), 1, 6);
  return test::scene_from_soup(soup, "bright closed room");
}

// Absorbed over emitted power in the bright closed room, from the exported
// interpolant, seen in part by a camera on one wall.
double bright_room_balance(const LinearOptions& base) {
  const Scene scene = bright_closed_room();
  MeshingOptions meshing;
  meshing.max_edge = default_max_edge(scene);
  MeshedScene model(scene, meshing);
  LinearOptions options = base;
  options.view = test::view_from(model, Vec3(2.5, 1.4, 0.3), Vec3(2.5, 1.4, 4.0), Vec3(0, 1, 0), 30.0, 128, 96);
  LinearSolver solver(model, options);
  solver.solve();
  const Rgb absorbed = test::absorbed_power(
      model, [&](int s) { return solver.vertex_radiance(s, model.hierarchy(s).conforming_mesh()); });
  double emitted = 0.0;
  for (int s = 0; s < model.num_surfaces(); ++s) emitted += M_PI * model.surface_area(s) * model.material(s).emission[0];
  EXPECT_GT(emitted, 0.0);
  return emitted > 0.0 ? absorbed[0] / emitted : 0.0;
}

// docs/accuracy.md, "Concave junctions": next to a concave edge the
// radiance bends down steeply, and the linear interpolant of exact vertex
// values carries less power than the surface has. The loss has one sign
// and every bounce repeats it (ρ 0.8: about five bounces' worth), while the
// camera, looking at one wall, leaves most junction elements to the
// object-space test. Measured: absorbed 0.9903 of emitted when that test
// split edges at 10⁻⁴ of the emitted power, 1.0000 at 10⁻⁵ (the default;
// 0.9983 since, with the oracle's later changes).
TEST(EnergyBalance, ABrightClosedRoomSeenInPartAbsorbsWhatItsLampEmits) {
  const double balance = bright_room_balance(LinearOptions{});
  EXPECT_NEAR(balance, 1.0, 0.005) << "absorbed / emitted = " << balance;
}

// The same loss is what --eps-power bounds (docs/accuracy.md, "The power
// bound"): ten times looser, the room loses a measurable share of its lamp.
// Both runs rescale their cluster links as their shooters' radiance changes
// shape: as made, the shape factors drawn from the first bounces keep an
// excess in this room (docs/accuracy.md, "A shape factor that ages") that is
// not this loss and would hide it.
TEST(EnergyBalance, ALooserPowerBoundLosesMoreAtTheJunctions) {
  LinearOptions fresh;
  fresh.rescale_cluster_links = true;
  LinearOptions loose = fresh;
  loose.eps_power = 10.0 * LinearOptions{}.eps_power;
  const double at_default = bright_room_balance(fresh);
  const double when_loose = bright_room_balance(loose);
  EXPECT_LT(when_loose, 0.995) << "absorbed / emitted at eps_power " << loose.eps_power;
  EXPECT_LT(when_loose, at_default - 0.0025) << "default " << at_default << ", loose " << when_loose;
}

// docs/accuracy.md, "A shape factor that ages": rescaling the cluster links
// by how the receiver's view of their shooters' parts moved, without rays,
// takes out what drawing every one of them again in every iteration does.
// Measured: as made 1.0021, drawn again 0.9919, rescaled 0.9919. The room
// must show the excess as made, or the agreement would say nothing.
TEST(EnergyBalance, RescaledClusterLinksTakeOutTheExcessAsDrawingAgainDoes) {
  LinearOptions rescaled;
  rescaled.rescale_cluster_links = true;
  LinearOptions redrawn;
  redrawn.redraw_cluster_links = true;
  const double as_made = bright_room_balance(LinearOptions{});
  const double by_rescaling = bright_room_balance(rescaled);
  const double by_drawing = bright_room_balance(redrawn);
  EXPECT_GT(as_made, by_drawing + 0.005) << "as made " << as_made << ", drawn again " << by_drawing;
  EXPECT_NEAR(by_rescaling, by_drawing, 0.002) << "as made " << as_made;
}

// The largest relative difference in luminance between a solve's values and
// the same solve's converged, value by value; infinite where the converged
// value is not positive (a closed room is lit everywhere).
double worst_relative_difference(const std::vector<std::vector<Rgb>>& stopped,
                                 const std::vector<std::vector<Rgb>>& converged) {
  double worst = 0.0;
  EXPECT_EQ(stopped.size(), converged.size());
  for (std::size_t s = 0; s < std::min(stopped.size(), converged.size()); ++s) {
    EXPECT_EQ(stopped[s].size(), converged[s].size());
    for (std::size_t k = 0; k < std::min(stopped[s].size(), converged[s].size()); ++k) {
      const double truth = luminance(converged[s][k]);
      if (!(truth > 0.0)) return std::numeric_limits<double>::infinity();
      worst = std::max(worst, std::abs(luminance(stopped[s][k]) - truth) / truth);
    }
  }
  return worst;
}

// docs/accuracy.md, "When the iteration stops": the stopping test is
// relative to each value, so the walls of a room lit by a lamp a hundred
// times brighter than they are must have converged when the solve stops,
// not only the lamp. On one discretisation (first links only), the
// default tolerance's vertices stand within ten times it of where the
// iteration converges (ρ 0.8 leaves about four times the last change to
// come); a test scaled by the lamp let the walls stop percents short.
TEST(EnergyBalance, TheIterationStopsWhenTheDimWallsHaveConvergedToo) {
  const Scene scene = bright_closed_room();
  MeshingOptions meshing;
  meshing.max_edge = default_max_edge(scene);
  MeshedScene model(scene, meshing);
  const auto solve = [&](double tolerance, int max_iterations) {
    LinearOptions options;
    options.max_links = 1;
    // Rescaled cluster links change the operator whenever a shooter's
    // shape moves by 1 %: the stopped and converged solves would then be
    // of different operators.
    options.rescale_cluster_links = false;
    options.tolerance = tolerance;
    options.max_iterations = max_iterations;
    options.view = test::view_from(model, Vec3(2.5, 1.4, 0.3), Vec3(2.5, 1.4, 4.0), Vec3(0, 1, 0), 30.0, 64, 48);
    LinearSolver solver(model, options);
    solver.solve();
    std::vector<std::vector<Rgb>> values;
    for (int s = 0; s < model.num_surfaces(); ++s) values.push_back(solver.vertex_radiance(s));
    return std::pair(values, solver.stats().iterations);
  };
  const LinearOptions defaults;
  const auto [stopped, iterations] = solve(defaults.tolerance, defaults.max_iterations);
  const auto [converged, converged_iterations] = solve(1e-9, 400);
  ASSERT_LT(iterations, defaults.max_iterations);
  ASSERT_LT(converged_iterations, 400);
  const double worst = worst_relative_difference(stopped, converged);
  ::testing::Test::RecordProperty("worst", std::to_string(worst));
  ::testing::Test::RecordProperty("iterations", iterations);
  EXPECT_LT(worst, 10.0 * defaults.tolerance) << "stopped after " << iterations << " iterations";
  EXPECT_GT(worst, 0.0) << "the converged solve must have gone further";
}

// The classical method's --tolerance means the same (docs/accuracy.md, "When
// the iteration stops"): the same room on its first links (ε_BF too coarse
// to refine any), its leaves at the default tolerance against the same solve
// converged to 10⁻⁹.
TEST(EnergyBalance, TheClassicalIterationStopsWhenTheDimWallsHaveConvergedToo) {
  const Scene scene = bright_closed_room();
  MeshingOptions meshing;
  meshing.max_edge = default_max_edge(scene);
  MeshedScene model(scene, meshing);
  const auto solve = [&](double tolerance, int max_iterations) {
    ClassicalOptions options;
    options.eps_bf = 1e9;
    options.tolerance = tolerance;
    options.max_iterations = max_iterations;
    ClassicalSolver solver(model, options);
    solver.solve();
    std::vector<std::vector<Rgb>> values(model.num_surfaces());
    for (int s = 0; s < model.num_surfaces(); ++s) {
      for (NodeId leaf : model.hierarchy(s).leaves()) values[s].push_back(solver.radiance(s, leaf));
    }
    return std::pair(values, solver.stats().iterations);
  };
  const ClassicalOptions defaults;
  const auto [stopped, iterations] = solve(defaults.tolerance, defaults.max_iterations);
  const auto [converged, converged_iterations] = solve(1e-9, 400);
  ASSERT_LT(iterations, defaults.max_iterations);
  ASSERT_LT(converged_iterations, 400);
  const double worst = worst_relative_difference(stopped, converged);
  ::testing::Test::RecordProperty("worst", std::to_string(worst));
  ::testing::Test::RecordProperty("iterations", iterations);
  EXPECT_LT(worst, 10.0 * defaults.tolerance) << "stopped after " << iterations << " iterations";
  EXPECT_GT(worst, 0.0) << "the converged solve must have gone further";
}

}  // namespace
}  // namespace lhr
