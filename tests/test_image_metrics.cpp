// The relative luminance norm (docs/design.md §5, the primary figure), the paper's
// display-value norm and the companion metrics on synthetic image pairs whose
// answers follow from their construction.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "render/image_metrics.hpp"

namespace lhr {
namespace {

// A linear tone map with white 1 and gamma 1 shows radiance as display
// value, so display differences are the radiance differences we build in.
const LinearToneMap kIdentity(1.0, 1.0);

Image constant_image(int w, int h, float value) {
  Image image(w, h);
  std::fill(image.rgb.begin(), image.rgb.end(), value);
  return image;
}

void set_pixel(Image& image, int x, int y, float r, float g, float b) {
  float* p = image.pixel(x, y);
  p[0] = r, p[1] = g, p[2] = b;
}

std::vector<std::uint8_t> all_pixels(const Image& image) {
  return std::vector<std::uint8_t>(static_cast<std::size_t>(image.width) * image.height, 1);
}

TEST(ImageMetrics, IdenticalImagesAgreeEverywhere) {
  Image reference = constant_image(8, 6, 0.3f);
  set_pixel(reference, 2, 3, 0.9f, 0.1f, 0.4f);
  const ImageMetrics m = compare_images(reference, reference, all_pixels(reference), kIdentity);
  EXPECT_EQ(m.pixels, 48u);
  EXPECT_EQ(m.within_10, 100.0);
  EXPECT_EQ(m.within_15, 100.0);
  EXPECT_EQ(m.rmse, 0.0);
  EXPECT_TRUE(std::isinf(m.psnr_db) && m.psnr_db > 0);
  EXPECT_EQ(m.max_difference, 0.0);
  EXPECT_EQ(m.relative_error, 0.0);
}

TEST(ImageMetrics, OnePixelOffByTwelvePercentIsOutsideTenButInsideFifteen) {
  const Image reference = constant_image(10, 10, 0.5f);
  Image image = reference;
  set_pixel(image, 4, 7, 0.62f, 0.62f, 0.62f);
  const ImageMetrics m = compare_images(image, reference, all_pixels(reference), kIdentity);
  const double d = 0.62f - 0.5f;  // the difference as stored in floats
  EXPECT_EQ(m.pixels, 100u);
  EXPECT_DOUBLE_EQ(m.within_10, 99.0);
  EXPECT_DOUBLE_EQ(m.within_15, 100.0);
  EXPECT_NEAR(m.max_difference, d, 1e-12);
  // One pixel of 100, all three channels off by d: mean square d²/100.
  EXPECT_NEAR(m.rmse, d / 10.0, 1e-12);
  EXPECT_NEAR(m.psnr_db, -20.0 * std::log10(d / 10.0), 1e-9);
  EXPECT_NEAR(m.relative_error, 3 * d / (300 * 0.5), 1e-12);
}

TEST(ImageMetrics, OneChannelOffIsEnoughToLeaveTheBand) {
  const Image reference = constant_image(4, 4, 0.5f);
  Image image = reference;
  set_pixel(image, 1, 1, 0.5f, 0.7f, 0.5f);  // green off by 20 % of the range
  const ImageMetrics m = compare_images(image, reference, all_pixels(reference), kIdentity);
  EXPECT_DOUBLE_EQ(m.within_10, 100.0 * 15 / 16);
  EXPECT_DOUBLE_EQ(m.within_15, 100.0 * 15 / 16);
}

TEST(ImageMetrics, ConstantOffsetsFallIntoTheirBands) {
  const Image reference = constant_image(5, 5, 0.25f);
  struct Case {
    float offset;
    double within_10, within_15;
  };
  for (const Case c : {Case{0.05f, 100, 100}, Case{0.125f, 0, 100}, Case{0.25f, 0, 0}, Case{-0.125f, 0, 100}}) {
    SCOPED_TRACE(c.offset);
    const Image image = constant_image(5, 5, 0.25f + c.offset);
    const ImageMetrics m = compare_images(image, reference, all_pixels(reference), kIdentity);
    EXPECT_EQ(m.within_10, c.within_10);
    EXPECT_EQ(m.within_15, c.within_15);
    EXPECT_NEAR(m.rmse, std::abs(c.offset), 1e-7);
    EXPECT_NEAR(m.max_difference, std::abs(c.offset), 1e-7);
    EXPECT_NEAR(m.relative_error, std::abs(c.offset) / 0.25, 1e-6);
  }
}

TEST(ImageMetrics, BandsAreMeasuredOnDisplayValuesNotRadiance) {
  // Through gamma 2.2, radiance 0.25 and 0.36 (11 % of white apart) display
  // as 0.25^(1/2.2) and 0.36^(1/2.2), which are less than 10 % apart.
  const LinearToneMap gamma(1.0, 2.2);
  const Image reference = constant_image(3, 3, 0.25f);
  const Image image = constant_image(3, 3, 0.36f);
  const double shown = std::pow(0.36f, 1 / 2.2) - std::pow(0.25f, 1 / 2.2);
  ASSERT_LT(shown, 0.10);
  const ImageMetrics m = compare_images(image, reference, all_pixels(reference), gamma);
  EXPECT_EQ(m.within_10, 100.0);
  EXPECT_NEAR(m.rmse, shown, 1e-9);
  // The linear error stays the radiance's.
  EXPECT_NEAR(m.relative_error, (0.36f - 0.25f) / 0.25f, 1e-6);
}

TEST(ImageMetrics, BackgroundPixelsAreLeftOut) {
  Image reference = constant_image(4, 4, 0.5f);
  set_pixel(reference, 0, 0, 0, 0, 0);
  set_pixel(reference, 3, 2, 0, 0, 0);
  Image image = reference;
  set_pixel(image, 0, 0, 1, 1, 1);  // a wildly different background pixel
  const auto mask = nonzero_mask(reference);
  EXPECT_EQ(std::count(mask.begin(), mask.end(), 1), 14);
  EXPECT_EQ(mask[0], 0);
  EXPECT_EQ(mask[2 * 4 + 3], 0);
  const ImageMetrics m = compare_images(image, reference, mask, kIdentity);
  EXPECT_EQ(m.pixels, 14u);
  EXPECT_EQ(m.within_10, 100.0);
  EXPECT_EQ(m.rmse, 0.0);
}

TEST(ImageMetrics, SizeMismatchIsAnError) {
  const Image a = constant_image(4, 4, 0.5f), b = constant_image(4, 5, 0.5f);
  EXPECT_THROW(compare_images(a, b, all_pixels(b), kIdentity), std::invalid_argument);
  EXPECT_THROW(compare_images(a, a, all_pixels(b), kIdentity), std::invalid_argument);
}

TEST(ImageMetrics, ReferenceToneMapTakesItsDefaultsFromTheMaskedReference) {
  // Linear tone map, white by default the brightest masked luminance: the
  // brighter pixel outside the mask must not set it.
  Image reference = constant_image(3, 1, 0.0f);
  set_pixel(reference, 0, 0, 2, 2, 2);
  set_pixel(reference, 1, 0, 1, 1, 1);
  set_pixel(reference, 2, 0, 8, 8, 8);
  const std::vector<std::uint8_t> mask{1, 1, 0};
  ToneMapSettings linear;
  linear.kind = ToneMapKind::kLinear;
  linear.gamma = 1.0;
  const auto tone = reference_tone_map(linear, reference, mask);
  EXPECT_NEAR(tone->display(2.0), 1.0, 1e-9);
  EXPECT_NEAR(tone->display(1.0), 0.5, 1e-9);
  // Tumblin–Rushmeier adapts to the log-average of the masked pixels, as the
  // view of a solution does.
  ToneMapSettings tr;
  const auto mapped = reference_tone_map(tr, reference, mask);
  tr.world_adaptation = log_average_luminance(reference, mask);
  const auto expected = make_tone_map(tr, 0.0, 0.0);
  for (double l : {0.1, 1.0, 2.0, 5.0}) EXPECT_DOUBLE_EQ(mapped->display(l), expected->display(l));
}

// Grey pixels: their luminance is their value (the Rec. 709 weights sum to 1).
Image grey_gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float v = 0.2f + 0.05f * static_cast<float>(x + w * y);
      set_pixel(image, x, y, v, v, v);
    }
  }
  return image;
}

Image scaled(const Image& image, float factor) {
  Image out = image;
  for (float& v : out.rgb) v *= factor;
  return out;
}

TEST(RelativeNorm, FivePercentTooBrightEverywhereIsWithinTenButNotFour) {
  const Image reference = grey_gradient(8, 6);
  const Image image = scaled(reference, 1.05f);
  const auto mask = all_pixels(reference);
  EXPECT_EQ(relative_within(image, reference, mask, 0.10), 100.0);
  EXPECT_EQ(relative_within(image, reference, mask, 0.06), 100.0);
  EXPECT_EQ(relative_within(image, reference, mask, 0.04), 0.0);
  EXPECT_NEAR(mean_luminance_ratio(image, reference, mask), 1.05, 1e-6);
  const ImageMetrics m = compare_images(image, reference, mask, kIdentity);
  EXPECT_EQ(m.rel_within_10, 100.0);
  EXPECT_EQ(m.rel_within_15, 100.0);
  EXPECT_NEAR(m.mean_ratio, 1.05, 1e-6);
  // Mean of 0.2 + 0.05 k for k = 0..47.
  EXPECT_NEAR(m.reference_mean_luminance, 0.2 + 0.05 * 47 / 2, 1e-6);
  // Colour does not matter, only luminance: a reddish reference, 5 % too dark.
  Image red = reference;
  for (std::size_t i = 0; i < red.rgb.size(); i += 3) red.rgb[i + 1] *= 0.5f, red.rgb[i + 2] *= 0.25f;
  EXPECT_EQ(relative_within(scaled(red, 0.95f), red, mask, 0.10), 100.0);
  EXPECT_EQ(relative_within(scaled(red, 0.95f), red, mask, 0.04), 0.0);
  EXPECT_NEAR(mean_luminance_ratio(scaled(red, 0.95f), red, mask), 0.95, 1e-6);
}

TEST(RelativeNorm, AFaceThirtyPercentTooBrightLosesExactlyItsPixels) {
  // A 10x10 image; a 3x4 block (a face of the scene) 30 % too bright.
  const Image reference = grey_gradient(10, 10);
  Image image = reference;
  for (int y = 2; y < 6; ++y) {
    for (int x = 5; x < 8; ++x) {
      float* p = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) p[c] *= 1.3f;
    }
  }
  const auto mask = all_pixels(reference);
  const ImageMetrics m = compare_images(image, reference, mask, kIdentity);
  EXPECT_DOUBLE_EQ(m.rel_within_10, 100.0 - 12.0);
  EXPECT_DOUBLE_EQ(m.rel_within_15, 100.0 - 12.0);
  EXPECT_EQ(relative_within(image, reference, mask, 0.31), 100.0);
  // The mean ratio: the face's extra luminance over the total.
  double face = 0.0, total = 0.0;
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 10; ++x) {
      const double v = reference.pixel(x, y)[0];
      total += v;
      if (y >= 2 && y < 6 && x >= 5 && x < 8) face += v;
    }
  }
  EXPECT_NEAR(m.mean_ratio, 1.0 + 0.3 * face / total, 1e-6);
  // The difference image paints exactly the face red (too bright).
  const Image diff = difference_image(image, reference, mask);
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 10; ++x) {
      const float* p = diff.pixel(x, y);
      const bool red = p[0] == 1.0f && p[1] == 0.0f && p[2] == 0.0f;
      EXPECT_EQ(red, y >= 2 && y < 6 && x >= 5 && x < 8) << x << ", " << y;
    }
  }
}

TEST(RelativeNorm, CatchesWhatTheDisplayNormMissesOnADimImage) {
  // A dim tone map (white far above the scene, gamma 1) turns a 30 % error on
  // a face into a display difference of 0.3 · 0.25 / 4 < 2 % of the range.
  const LinearToneMap dim(4.0, 1.0);
  const Image reference = constant_image(5, 4, 0.25f);
  Image image = reference;
  for (int x = 0; x < 5; ++x) set_pixel(image, x, 0, 0.325f, 0.325f, 0.325f);
  const ImageMetrics m = compare_images(image, reference, all_pixels(reference), dim);
  EXPECT_EQ(m.within_10, 100.0);
  EXPECT_EQ(m.within_15, 100.0);
  EXPECT_DOUBLE_EQ(m.rel_within_10, 75.0);
  EXPECT_DOUBLE_EQ(m.rel_within_15, 75.0);
}

TEST(RelativeNorm, NearBlackPixelsAreJudgedAgainstTheFloor) {
  // 98 pixels at 1 and 2 black: mean Y_ref 0.98, floor 0.0098, so within 10 %
  // allows an absolute error of 0.00098 on a black pixel.
  Image reference = constant_image(10, 10, 1.0f);
  set_pixel(reference, 3, 3, 0, 0, 0);
  set_pixel(reference, 6, 7, 0, 0, 0);
  Image image = reference;
  set_pixel(image, 3, 3, 0.0009f, 0.0009f, 0.0009f);  // inside the floor
  set_pixel(image, 6, 7, 0.0011f, 0.0011f, 0.0011f);  // outside it
  const auto mask = all_pixels(reference);
  EXPECT_DOUBLE_EQ(relative_within(image, reference, mask, 0.10), 99.0);
  // Without a floor both are infinitely far off.
  EXPECT_DOUBLE_EQ(relative_within(image, reference, mask, 0.10, 0.0), 98.0);
  // A larger floor lets both in.
  EXPECT_DOUBLE_EQ(relative_within(image, reference, mask, 0.10, 0.02), 100.0);
  // A dim pixel above the floor is judged relative to itself: 0.05 off by 0.004 is 8 %.
  Image dim_reference = reference;
  set_pixel(dim_reference, 3, 3, 0.05f, 0.05f, 0.05f);
  Image dim_image = image;
  set_pixel(dim_image, 3, 3, 0.054f, 0.054f, 0.054f);
  EXPECT_DOUBLE_EQ(relative_within(dim_image, dim_reference, mask, 0.10), 99.0);  // the black one still off
  EXPECT_DOUBLE_EQ(relative_within(dim_image, dim_reference, mask, 0.07), 98.0);
}

TEST(RelativeNorm, BackgroundIsLeftOutOfTheCountsAndTheMean) {
  Image reference = constant_image(4, 4, 0.5f);
  set_pixel(reference, 0, 0, 5000, 5000, 5000);  // a bright background pixel
  Image image = scaled(reference, 1.2f);          // 20 % too bright everywhere...
  set_pixel(image, 0, 0, 0, 0, 0);                // ...but in the background
  std::vector<std::uint8_t> mask = all_pixels(reference);
  mask[0] = 0;
  const ImageMetrics m = compare_images(image, reference, mask, kIdentity);
  EXPECT_EQ(m.pixels, 15u);
  // Were the background in the mean (~313), the floor (1 % of it) would let
  // every 0.1 error count as within 10 %.
  EXPECT_EQ(m.rel_within_10, 0.0);
  EXPECT_EQ(m.rel_within_15, 0.0);
  EXPECT_EQ(relative_within(image, reference, mask, 0.25), 100.0);
  EXPECT_NEAR(m.mean_ratio, 1.2, 1e-6);
  EXPECT_NEAR(m.reference_mean_luminance, 0.5, 1e-9);
}

TEST(RelativeNorm, SizeMismatchAndBadTolerancesAreErrors) {
  const Image a = constant_image(4, 4, 0.5f), b = constant_image(4, 5, 0.5f);
  EXPECT_THROW(relative_within(a, b, all_pixels(b), 0.1), std::invalid_argument);
  EXPECT_THROW(relative_within(a, a, all_pixels(b), 0.1), std::invalid_argument);
  EXPECT_THROW(mean_luminance_ratio(a, b, all_pixels(b)), std::invalid_argument);
  EXPECT_THROW(difference_image(a, b, all_pixels(b)), std::invalid_argument);
  EXPECT_THROW(relative_within(a, a, all_pixels(a), -0.1), std::invalid_argument);
  EXPECT_THROW(relative_within(a, a, all_pixels(a), 0.1, std::nan("")), std::invalid_argument);
}

TEST(RelativeNorm, MeanRatioOfBlackImages) {
  const Image black = constant_image(3, 3, 0.0f);
  const auto mask = all_pixels(black);
  EXPECT_EQ(mean_luminance_ratio(black, black, mask), 1.0);
  EXPECT_TRUE(std::isinf(mean_luminance_ratio(constant_image(3, 3, 0.1f), black, mask)));
  EXPECT_EQ(relative_within(black, black, mask, 0.1), 100.0);
}

TEST(ImageMetrics, DifferenceImageShowsTheRelativeBandsAndTheSign) {
  const Image reference = constant_image(6, 1, 0.5f);
  Image image = reference;
  set_pixel(image, 1, 0, 0.54f, 0.54f, 0.54f);    // 8 %: grey, brighter than exact
  set_pixel(image, 2, 0, 0.565f, 0.565f, 0.565f);  // 13 %: yellow
  set_pixel(image, 3, 0, 0.65f, 0.65f, 0.65f);    // 30 % too bright: red
  set_pixel(image, 4, 0, 0.35f, 0.35f, 0.35f);    // 30 % too dark: blue
  const std::vector<std::uint8_t> mask{1, 1, 1, 1, 1, 0};
  const Image diff = difference_image(image, reference, mask);
  const float* same = diff.pixel(0, 0);
  const float* close = diff.pixel(1, 0);
  EXPECT_GT(same[0], 0.0f);
  for (const float* grey : {same, close}) {
    EXPECT_EQ(grey[0], grey[1]);
    EXPECT_EQ(grey[1], grey[2]);
  }
  EXPECT_GT(close[0], same[0]);
  EXPECT_GT(diff.pixel(2, 0)[0], 0.5f);  // yellow: red and green, no blue
  EXPECT_GT(diff.pixel(2, 0)[1], 0.5f);
  EXPECT_EQ(diff.pixel(2, 0)[2], 0.0f);
  EXPECT_GT(diff.pixel(3, 0)[0], 0.5f);  // red
  EXPECT_EQ(diff.pixel(3, 0)[1], 0.0f);
  EXPECT_EQ(diff.pixel(3, 0)[2], 0.0f);
  EXPECT_EQ(diff.pixel(4, 0)[0], 0.0f);  // blue
  EXPECT_GT(diff.pixel(4, 0)[2], 0.5f);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(diff.pixel(5, 0)[c], 0.0f);  // background black
}

}  // namespace
}  // namespace lhr
