// Tone mapping: the Tumblin–Rushmeier operator's defining properties.

#include <gtest/gtest.h>

#include <cmath>

#include "radiosity/tone_map.hpp"

namespace lhr {
namespace {

TEST(ToneMap, TumblinRushmeierIsTheIdentityWhenWorldAdaptsLikeTheDisplay) {
  // With L_wa = L_da (= L_dmax/√C_max) α and β agree, so L_d = L_w.
  TumblinRushmeierParams p;
  p.world_adaptation = p.display_max_cd_m2 / std::sqrt(p.max_contrast);
  const TumblinRushmeierToneMap tr(p);
  for (double l : {0.1, 1.0, 7.5, 42.0, 90.0}) EXPECT_NEAR(tr.display_luminance_cd_m2(l), l, 1e-9 * l);
}

TEST(ToneMap, TumblinRushmeierIsMonotoneAndBounded) {
  TumblinRushmeierParams p;
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

TEST(ToneMap, BrighterAdaptationDarkensTheSameLuminance) {
  TumblinRushmeierParams dim, bright;
  dim.world_adaptation = 1.0;
  bright.world_adaptation = 100.0;
  EXPECT_GT(TumblinRushmeierToneMap(dim).display(5.0), TumblinRushmeierToneMap(bright).display(5.0));
}

TEST(ToneMap, ColourKeepsItsHueUnderTumblinRushmeier) {
  // Channels are scaled by one factor L_d/L_w before the black offset 1/C_max.
  TumblinRushmeierParams p;
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
  TumblinRushmeierParams p;
  p.world_adaptation = 0.0;
  EXPECT_THROW(TumblinRushmeierToneMap{p}, std::invalid_argument);
  EXPECT_THROW(LinearToneMap(-1.0), std::invalid_argument);
}

}  // namespace
}  // namespace lhr
