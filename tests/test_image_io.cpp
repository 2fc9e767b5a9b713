// PNG and EXR files through OpenImageIO.

#include <gtest/gtest.h>

#include "io/image_io.hpp"
#include "io/input_error.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

Image gradient(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = img.pixel(x, y);
      p[0] = static_cast<float>(x) / (w - 1);
      p[1] = static_cast<float>(y) / (h - 1);
      p[2] = 0.25f;
    }
  return img;
}

TEST(ImageIo, PngRoundTripsToEightBits) {
  const auto dir = test::fresh_dir("image_png");
  const Image img = gradient(17, 9);
  write_image(dir / "g.png", img);
  const Image back = read_image(dir / "g.png");
  ASSERT_EQ(back.width, 17);
  ASSERT_EQ(back.height, 9);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) EXPECT_NEAR(back.rgb[i], img.rgb[i], 0.5 / 255 + 1e-6);
  // Row 0 is the top: the green channel grows downwards.
  EXPECT_LT(back.pixel(0, 0)[1], back.pixel(0, 8)[1]);
}

TEST(ImageIo, ExrKeepsLinearValuesAboveOne) {
  const auto dir = test::fresh_dir("image_exr");
  Image img(4, 3);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = 0.1f * static_cast<float>(i) + 2.0f;
  write_image(dir / "l.exr", img);
  const Image back = read_image(dir / "l.exr");
  for (std::size_t i = 0; i < img.rgb.size(); ++i) EXPECT_NEAR(back.rgb[i], img.rgb[i], 2e-3 * img.rgb[i]);
}

TEST(ImageIo, FailuresLeaveNoFile) {
  const auto dir = test::fresh_dir("image_fail");
  EXPECT_THROW(write_image(dir / "x.bmpq", gradient(2, 2)), std::runtime_error);
  EXPECT_THROW(write_image(dir / "missing" / "x.png", gradient(2, 2)), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  EXPECT_THROW(read_image(dir / "none.png"), InputError);
  test::write_text(dir / "junk.png", "not a png at all");
  EXPECT_THROW(read_image(dir / "junk.png"), InputError);
}

}  // namespace
}  // namespace lhr
