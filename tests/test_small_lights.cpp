// Small lights close to a surface (docs/design.md §5 "small lights close to
// surfaces"): a non-reflecting square light of side a and radiance 1/a²
// (power π whatever a) faces a 10×10 wall of ρ = 0.7 from height d. The
// wall's reflected radiance integrated over it must be
//   ∫ L dA = ρ Le ∫_wall F(x→light) dA = ρ Le A_light F(light→wall),
// at most ρ (all the light's power reaching the wall) and close to it when d
// is small, and no point of the wall can be brighter than ρ·Le (the light
// fills at most its whole hemisphere).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "mesh/initial_mesh.hpp"
#include "radiosity/form_factor.hpp"
#include "render/solution.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

constexpr double kWall = 10.0;
constexpr double kRho = 0.7;

struct SmallLight {
  double side;
  double height;
  // Where the light's centre is over the wall: its middle by default; off it,
  // the light need not be near any vertex of the initial mesh.
  double x = 0.5 * kWall;
  double y = 0.5 * kWall;
  double radiance() const { return 1.0 / (side * side); }
  std::array<Vec3, 4> polygon() const {
    const double h = side / 2, z = height;
    return {Vec3(x - h, y - h, z), Vec3(x - h, y + h, z), Vec3(x + h, y + h, z), Vec3(x + h, y - h, z)};
  }
};

// The wall (surface group 0, z = 0, facing +z) and the lights (group 1, one
// material: the first light's radiance) over it, facing down.
Scene small_lights_scene(const std::vector<SmallLight>& lights) {
  PolygonSoup soup;
  Material wall;
  wall.name = "wall";
  wall.reflectance = Rgb(kRho, kRho, kRho);
  Material lamp;
  lamp.name = "light";
  lamp.reflectance = Rgb(0, 0, 0);
  const double radiance = lights.front().radiance();
  lamp.emission = Rgb(radiance, radiance, radiance);
  soup.materials = {wall, lamp};
  soup.groups = {"wall", "light"};
  test::add_quad(soup, Vec3(0, 0, 0), Vec3(kWall, 0, 0), Vec3(kWall, kWall, 0), Vec3(0, kWall, 0), 0, 0);
  for (const SmallLight& light : lights) {
    const std::array<Vec3, 4> p = light.polygon();
    test::add_quad(soup, p[0], p[1], p[2], p[3], 1, 1);
  }
  return test::scene_from_soup(soup, "small lights");
}

// Gauss–Legendre nodes and weights on [−1, 1].
std::vector<std::array<double, 2>> gauss_legendre(int n) {
  std::vector<std::array<double, 2>> out;
  for (int i = 1; i <= n; ++i) {
    double x = std::cos(M_PI * (i - 0.25) / (n + 0.5));
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / dp;
      x -= step;
      if (std::abs(step) < 1e-15) break;
    }
    out.push_back({x, 2.0 / ((1.0 - x * x) * dp * dp)});
  }
  return out;
}

// ∫_wall F(x→light) dA from the exact point-to-polygon form factor (Lambert's
// contour formula), independent of both solvers: a tensor Gauss rule on
// intervals graded geometrically toward the light's centre and the shadows of
// its edges, where the integrand varies on the scale of the height.
double exact_wall_integral(const SmallLight& light, int order) {
  const auto rule = [&](double centre) {
    std::set<double> cuts{0.0, kWall};
    const double scale = std::min(light.height, light.side) / 8.0;
    for (double at : {centre - light.side / 2, centre, centre + light.side / 2}) {
      for (double step = scale; step < kWall; step *= 2.0) {
        for (double c : {at - step, at + step}) {
          if (c > 0 && c < kWall) cuts.insert(c);
        }
      }
      if (at > 0 && at < kWall) cuts.insert(at);
    }
    const std::vector<double> edges(cuts.begin(), cuts.end());
    std::vector<std::array<double, 2>> points;  // abscissa, weight
    for (const auto& [x, w] : gauss_legendre(order)) {
      for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
        const double half = 0.5 * (edges[i + 1] - edges[i]);
        points.push_back({edges[i] + half * (1.0 + x), half * w});
      }
    }
    return points;
  };
  const std::array<Vec3, 4> polygon = light.polygon();
  double sum = 0.0;
  for (const auto& [x, wx] : rule(light.x)) {
    for (const auto& [y, wy] : rule(light.y)) {
      sum += wx * wy * point_polygon_form_factor(Vec3(x, y, 0), Vec3(0, 0, 1), polygon);
    }
  }
  return sum;
}

struct WallResult {
  double integral = 0.0;  // ∫ L dA over the exported wall
  double brightest = 0.0;
};

// ∫ L dA of the wall as exported: every triangle's area times the mean of its
// three vertex radiances (the piecewise-linear function users get).
WallResult solve_wall(const Scene& scene, double light_height, SolveMethod method) {
  SolveSettings settings;
  settings.method = method;
  settings.meshing.max_edge = default_max_edge(scene);
  settings.camera = framing_camera(scene);
  const Solution solution = solve_scene(scene, settings);
  const ExportMesh& mesh = solution.view.export_mesh;
  WallResult out;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    if (std::max({a[2], b[2], c[2]}) > 0.5 * light_height) continue;  // the lights' own faces
    const double area = 0.5 * OpenMesh::cross(b - a, c - a).norm();
    double mean = 0.0;
    for (int k = 0; k < 3; ++k) mean += luminance(mesh.radiance[t[k]]) / 3.0;
    out.integral += area * mean;
    for (int k = 0; k < 3; ++k) out.brightest = std::max(out.brightest, luminance(mesh.radiance[t[k]]));
  }
  return out;
}

class SmallLights : public ::testing::TestWithParam<SmallLight> {};

TEST_P(SmallLights, BothMethodsConserveTheLightsPowerOnTheWall) {
  const SmallLight light = GetParam();
  const double wall_integral = exact_wall_integral(light, 6);
  // The quadrature is its own check: a higher order on the same intervals agrees.
  ASSERT_NEAR(exact_wall_integral(light, 9), wall_integral, 1e-5 * wall_integral);
  const double exact = kRho * light.radiance() * wall_integral;
  ASSERT_LE(exact, kRho * (1.0 + 1e-6)) << "at most the light's whole power reaches the wall";
  for (SolveMethod method : {SolveMethod::kLinear, SolveMethod::kClassical}) {
    const WallResult r = solve_wall(small_lights_scene({light}), light.height, method);
    EXPECT_NEAR(r.integral, exact, 0.03 * exact) << method_name(method) << ": ∫L dA / exact = " << r.integral / exact;
    EXPECT_LE(r.brightest, kRho * light.radiance() * (1.0 + 1e-6)) << method_name(method);
  }
}

// A panel of small lights (docs/design.md §3, "Panels of lights"): sixteen
// lamps of side 0.1 at height 0.1, each of radiance 1/a², about two metres
// apart and off the wall's initial vertices, are one surface, which shoots
// first as one cluster. Its links must open down to each lamp where the wall
// is near it, so ∫L dA is still the sum of the lamps' exact integrals and no
// point is brighter than one lamp can make it, with both methods.
TEST(SmallLights, APanelOfSmallLightsIsOneSurfaceThatDeliversEachLampsPower) {
  std::vector<SmallLight> lamps;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) lamps.push_back({0.1, 0.1, 2.3 + 1.9 * i + 0.07 * j, 2.1 + 2.0 * j + 0.05 * i});
  }
  double exact = 0.0;
  for (const SmallLight& l : lamps) exact += kRho * l.radiance() * exact_wall_integral(l, 6);
  const Scene scene = small_lights_scene(lamps);
  ASSERT_EQ(scene.surfaces.size(), 2u) << "the sixteen lamps are one surface";
  for (SolveMethod method : {SolveMethod::kLinear, SolveMethod::kClassical}) {
    const WallResult r = solve_wall(scene, lamps[0].height, method);
    EXPECT_NEAR(r.integral, exact, 0.03 * exact) << method_name(method) << ": ∫L dA / exact = " << r.integral / exact;
    EXPECT_LE(r.brightest, kRho * lamps[0].radiance() * (1.0 + 1e-6)) << method_name(method);
  }
}

std::string case_name(const ::testing::TestParamInfo<SmallLight>& info) {
  const auto digits = [](double v) {
    std::string s = std::to_string(v);
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
    std::replace(s.begin(), s.end(), '.', '_');
    return s;
  };
  const bool centred = info.param.x == 0.5 * kWall && info.param.y == 0.5 * kWall;
  return "side_" + digits(info.param.side) + "_height_" + digits(info.param.height) + (centred ? "" : "_off_centre");
}

// Every light of side 0.1 and 0.01 at a height d ≤ a, and the smallest two
// away from the wall's middle: about a second each. Farther off (d up to 1,
// a hundred times the side), the spot is wide and smooth.
INSTANTIATE_TEST_SUITE_P(Small, SmallLights,
                         ::testing::Values(SmallLight{0.1, 0.1}, SmallLight{0.1, 0.01}, SmallLight{0.1, 0.001},
                                           SmallLight{0.01, 0.01}, SmallLight{0.01, 0.001},
                                           SmallLight{0.1, 1}, SmallLight{0.01, 0.1}, SmallLight{0.01, 1},
                                           SmallLight{0.1, 0.001, 2.2222, 7.377},
                                           SmallLight{0.01, 0.001, 5.3137, 4.7711}),
                         case_name);

// A light of side 1 is not small against the wall's mesh: both methods are
// within 0.3 % on it. The farthest runs in every build; nearer ones, whose
// large bright spot the image-space refinement resolves in 2 to 12 seconds
// per case, are `slow` (tests/CMakeLists.txt): release builds only.
INSTANTIATE_TEST_SUITE_P(LargeLight, SmallLights, ::testing::Values(SmallLight{1, 1}), case_name);
INSTANTIATE_TEST_SUITE_P(LargeLightNear, SmallLights,
                         ::testing::Values(SmallLight{1, 0.1}, SmallLight{1, 0.01}, SmallLight{1, 0.001}),
                         case_name);

}  // namespace
}  // namespace lhr
