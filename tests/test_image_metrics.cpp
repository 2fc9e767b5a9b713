// The paper's image norms and the companion metrics (DESIGN §5 "Metrics") on
// synthetic image pairs whose answers follow from their construction.

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
  ToneMapChoice choice;
  choice.kind = ToneMapChoice::Kind::kLinear;
  choice.gamma = 1.0;
  const auto tone = reference_tone_map(choice, reference, mask);
  EXPECT_NEAR(tone->display(2.0), 1.0, 1e-9);
  EXPECT_NEAR(tone->display(1.0), 0.5, 1e-9);
  // Tumblin–Rushmeier adapts to the log-average of the masked pixels, as the
  // view of a solution does.
  ToneMapChoice tr;
  const auto mapped = reference_tone_map(tr, reference, mask);
  tr.world_adaptation = log_average_luminance(reference, mask);
  const auto expected = make_tone_map(tr, 0.0, 0.0);
  for (double l : {0.1, 1.0, 2.0, 5.0}) EXPECT_DOUBLE_EQ(mapped->display(l), expected->display(l));
}

TEST(ImageMetrics, DifferenceImageShowsTheBands) {
  const Image reference = constant_image(4, 1, 0.5f);
  Image image = reference;
  set_pixel(image, 1, 0, 0.62f, 0.62f, 0.62f);  // 12 %: yellow
  set_pixel(image, 2, 0, 0.8f, 0.8f, 0.8f);     // 30 %: red
  const std::vector<std::uint8_t> mask{1, 1, 1, 0};
  const Image diff = difference_image(image, reference, mask, kIdentity);
  const float* same = diff.pixel(0, 0);
  EXPECT_GT(same[0], 0.0f);
  EXPECT_EQ(same[0], same[1]);
  EXPECT_EQ(same[1], same[2]);
  EXPECT_GT(diff.pixel(1, 0)[1], 0.5f);  // yellow: red and green, no blue
  EXPECT_EQ(diff.pixel(1, 0)[2], 0.0f);
  EXPECT_EQ(diff.pixel(2, 0)[1], 0.0f);  // red
  EXPECT_GT(diff.pixel(2, 0)[0], 0.5f);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(diff.pixel(3, 0)[c], 0.0f);  // background black
}

}  // namespace
}  // namespace lhr
