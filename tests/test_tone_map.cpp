// Tone mapping: the Tumblin–Rushmeier operator's defining properties, and that
// it never inverts or flattens, whatever the adaptation (docs/design.md §4).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "io/scene_loader.hpp"
#include "radiosity/tone_map.hpp"
#include "render/solution.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

TEST(ToneMap, TumblinRushmeierIsTheIdentityWhenWorldAdaptsLikeTheDisplay) {
  // With L_wa = L_da (= L_dmax/√C_max) α and β agree, so L_d = L_w.
  ToneMapSettings p;
  p.world_adaptation = p.display_max_cd_m2 / std::sqrt(p.max_contrast);
  const TumblinRushmeierToneMap tr(p);
  for (double l : {0.1, 1.0, 7.5, 42.0, 90.0}) EXPECT_NEAR(tr.display_luminance_cd_m2(l), l, 1e-9 * l);
}

TEST(ToneMap, TumblinRushmeierIsMonotoneAndBounded) {
  ToneMapSettings p;
  p.world_adaptation = 3.0;
  const TumblinRushmeierToneMap tr(p);
  double previous = -1.0;
  for (double l = 1e-4; l < 1e4; l *= 1.3) {
    const double d = tr.display(l);
    EXPECT_GE(d, previous);
    EXPECT_GE(d, 0.0);
    EXPECT_LE(d, 1.0);
    previous = d;
  }
  EXPECT_EQ(tr.display(0.0), 0.0);
  EXPECT_EQ(tr.display(-1.0), 0.0);
  EXPECT_FALSE(std::isnan(tr.display(std::nan(""))));
}

// Adaptation levels from 10⁻⁸ to 10⁶ cd/m², a quarter decade apart.
std::vector<double> adaptations_cd_m2() {
  std::vector<double> out;
  for (int q = -32; q <= 24; ++q) out.push_back(std::pow(10.0, q / 4.0));
  return out;
}

TEST(ToneMap, TumblinRushmeierNeverInvertsAtAnyAdaptation) {
  for (const double adaptation : adaptations_cd_m2()) {
    SCOPED_TRACE(adaptation);
    ToneMapSettings p;
    p.world_adaptation = adaptation;
    const TumblinRushmeierToneMap tr(p);
    // 10⁻¹⁰..10¹⁰ × the adaptation, 40 steps a decade.
    double previous = -1.0, previous_cd = -1.0, lowest_near = 2.0, highest_near = -1.0;
    for (int i = -400; i <= 400; ++i) {
      const double l = adaptation * std::pow(10.0, i / 40.0);
      const double d = tr.display(l);
      const double cd = tr.display_luminance_cd_m2(l);
      ASSERT_TRUE(std::isfinite(d)) << l;
      ASSERT_GE(d, 0.0) << l;
      ASSERT_LE(d, 1.0) << l;
      ASSERT_GE(d, previous) << l;
      // Before the display's clamp the map is a power law with a positive
      // exponent, so it rises strictly wherever it stays representable.
      if (previous_cd > 0 && std::isfinite(cd)) {
        ASSERT_GT(cd, previous_cd) << l;
      }
      previous = d;
      previous_cd = cd;
      if (std::abs(i) <= 160) {
        lowest_near = std::min(lowest_near, d);
        highest_near = std::max(highest_near, d);
      }
    }
    // Within four decades of the adaptation the displayed value must change:
    // a flattened (exponent 0) or constant map fails here.
    EXPECT_LT(lowest_near, highest_near);
  }
}

TEST(ToneMap, TumblinRushmeierGuardsTheWorldLuminance) {
  for (const double adaptation : {1e-8, 1.0, 1e6}) {
    ToneMapSettings p;
    p.world_adaptation = adaptation;
    const TumblinRushmeierToneMap tr(p);
    EXPECT_EQ(tr.display(0.0), 0.0);
    EXPECT_EQ(tr.display(std::numeric_limits<double>::denorm_min()), 0.0);
    EXPECT_EQ(tr.display(std::numeric_limits<double>::max()), 1.0);
    EXPECT_EQ(tr.display(std::numeric_limits<double>::infinity()), 1.0);
    EXPECT_EQ(tr.display(std::nan("")), 0.0);
    const double big = std::numeric_limits<double>::max();
    const Rgb huge = tr.display_rgb(Rgb(big, big, 0.0));
    EXPECT_EQ(huge[0], 1.0);
    EXPECT_EQ(huge[1], 1.0);
    EXPECT_EQ(huge[2], 0.0);
    const Rgb odd = tr.display_rgb(Rgb(std::numeric_limits<double>::infinity(), std::nan(""), -1.0));
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(odd[k]));
    EXPECT_EQ(odd[0], 1.0);
  }
}

TEST(ToneMap, TumblinRushmeierColourKeepsOrderAndGrowsWithScale) {
  const Rgb colour(0.9, 0.3, 0.05);
  for (const double adaptation : adaptations_cd_m2()) {
    SCOPED_TRACE(adaptation);
    ToneMapSettings p;
    p.world_adaptation = adaptation;
    const TumblinRushmeierToneMap tr(p);
    Rgb previous(-1, -1, -1);
    for (int i = -400; i <= 400; i += 2) {
      const double scale = adaptation * std::pow(10.0, i / 40.0);
      const Rgb d = tr.display_rgb(scale * colour);
      for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(std::isfinite(d[k]));
        ASSERT_GE(d[k], 0.0);
        ASSERT_LE(d[k], 1.0);
        ASSERT_GE(d[k], previous[k]) << "channel " << k << " at scale " << scale;
      }
      ASSERT_GE(d[0], d[1]);
      ASSERT_GE(d[1], d[2]);
      previous = d;
    }
    EXPECT_GT(previous[0], 0.0);
  }
}

TEST(ToneMap, AHotspotIsNoDarkerThanItsDimSurroundAtVeryLowAdaptation) {
  // Adapted to 10⁻⁸ cd/m² the unclamped model has α(L_wa) < 0 and maps a light a
  // hundred or a million times brighter than its surround to less than it.
  ToneMapSettings p;
  p.world_adaptation = 1e-8;
  const TumblinRushmeierToneMap tr(p);
  for (const double ratio : {1e2, 1e6}) {
    EXPECT_GE(tr.display(ratio * p.world_adaptation), tr.display(p.world_adaptation));
    EXPECT_GT(tr.display_luminance_cd_m2(ratio * p.world_adaptation),
              tr.display_luminance_cd_m2(p.world_adaptation));
  }
  // A lamp's 1000 cd/m² still shows, however dark the surround.
  EXPECT_GT(tr.display(1e3), 0.0);
}

TEST(ToneMap, TheCornellBoxLitAtAMillionthCandelaIsNotInverted) {
  // `--units-to-cd 1e-6` puts the room's adaptation near 5·10⁻⁸ cd/m², where
  // the unclamped map showed the light darker than the floor. The room is then
  // too dark to see (both display values may be 0), so the order is checked on
  // the display luminance before the display's black level as well.
  const Scene scene = load_scene(test::source_dir() / "data/cornell/cornell.scene.json").scene;
  ASSERT_TRUE(scene.camera.has_value());
  SolveSettings settings;
  settings.camera = *scene.camera;
  settings.meshing.max_edge = 140.0;
  settings.linear.eps_link = 40.0;
  settings.tone.units_to_cd_m2 = 1e-6;
  const Solution solution = solve_scene(scene, settings);
  const ExportMesh& mesh = solution.view.export_mesh;
  const auto* tone = dynamic_cast<const TumblinRushmeierToneMap*>(solution.view.tone_map.get());
  ASSERT_NE(tone, nullptr);

  // The light (Ke 17 12 4 on the ceiling) against the floor (y = 0).
  double light = 0.0, floor = 0.0;
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    const double l = luminance(mesh.radiance[v]);
    if (l > 10.0) light = std::max(light, l);
    if (std::abs(mesh.points[v][1]) < 1e-6) floor = std::max(floor, l);
  }
  ASSERT_GT(light, 10.0 * floor);
  ASSERT_GT(floor, 0.0);
  EXPECT_GE(tone->display(light), tone->display(floor));
  EXPECT_GT(tone->display_luminance_cd_m2(light), tone->display_luminance_cd_m2(floor));

  // The same radiances a thousand times brighter are visible, and ordered.
  ToneMapSettings brighter = settings.tone;
  brighter.units_to_cd_m2 = 1e-3;
  const auto shown = make_tone_map(brighter, solution.view.world_adaptation, light);
  EXPECT_GT(shown->display(floor), 0.0);
  EXPECT_GT(shown->display(light), shown->display(floor));
}

TEST(ToneMap, BrighterAdaptationDarkensTheSameLuminance) {
  ToneMapSettings dim, bright;
  dim.world_adaptation = 1.0;
  bright.world_adaptation = 100.0;
  EXPECT_GT(TumblinRushmeierToneMap(dim).display(5.0), TumblinRushmeierToneMap(bright).display(5.0));
}

TEST(ToneMap, ColourKeepsItsHueUnderTumblinRushmeier) {
  // Channels are scaled by one factor L_d/L_w before the black offset 1/C_max.
  ToneMapSettings p;
  p.gamma = 1.0;
  p.world_adaptation = 2.0;
  const TumblinRushmeierToneMap tr(p);
  const Rgb c = tr.display_rgb(Rgb(2.0, 4.0, 1.0));
  for (int k = 0; k < 3; ++k) {
    ASSERT_GT(c[k], 0.0);
    ASSERT_LT(c[k], 1.0);
  }
  const double offset = 1.0 / p.max_contrast;
  EXPECT_NEAR((c[1] + offset) / (c[0] + offset), 2.0, 1e-9);
  EXPECT_NEAR((c[2] + offset) / (c[0] + offset), 0.5, 1e-9);
}

TEST(ToneMap, LinearMapsWhiteToOne) {
  const LinearToneMap lin(4.0, 1.0);
  EXPECT_DOUBLE_EQ(lin.display(2.0), 0.5);
  EXPECT_DOUBLE_EQ(lin.display(8.0), 1.0);
  const auto bytes = lin.display_bytes(Rgb(4.0, 2.0, 0.0));
  EXPECT_EQ(bytes[0], 255);
  EXPECT_EQ(bytes[1], 128);
  EXPECT_EQ(bytes[2], 0);
}

TEST(ToneMap, RejectsNonsenseParameters) {
  ToneMapSettings p;
  p.world_adaptation = 0.0;
  EXPECT_THROW(TumblinRushmeierToneMap{p}, std::invalid_argument);
  EXPECT_THROW(LinearToneMap(-1.0), std::invalid_argument);
}

}  // namespace
}  // namespace lhr
