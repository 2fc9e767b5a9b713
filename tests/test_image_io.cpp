// PNG and EXR files through OpenImageIO.

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>

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

TEST(ImageIo, ExrIsFullFloatAndCarriesItsCameraAndSoftware) {
  const auto dir = test::fresh_dir("image_exr_metadata");
  Image img(40, 30);
  img.rgb[0] = 1.0f + 1e-6f;  // half float would round this to 1
  Camera camera;
  camera.eye = Vec3(1, 2, 3);
  camera.target = Vec3(1, 2, 13);
  camera.up = Vec3(0, 1, 0);
  camera.fov_y_deg = 60;
  camera.width = 40;
  camera.height = 30;
  ImageMetadata metadata;
  metadata.software = "lhr 9.9.9";
  metadata.camera = camera;
  metadata.notes = {{"lhr:content", "linear radiance"}};
  write_image(dir / "m.exr", img, metadata);
  EXPECT_EQ(read_image(dir / "m.exr").rgb[0], 1.0f + 1e-6f);

  auto in = OIIO::ImageInput::open((dir / "m.exr").string());
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(spec.get_string_attribute("Software"), "lhr 9.9.9");
  EXPECT_EQ(spec.get_string_attribute("lhr:content"), "linear radiance");
  std::array<float, 16> to_camera{}, to_ndc{};
  ASSERT_TRUE(spec.getattribute("worldtocamera", OIIO::TypeMatrix, to_camera.data()));
  ASSERT_TRUE(spec.getattribute("worldtoscreen", OIIO::TypeMatrix, to_ndc.data()));
  const auto apply = [](const std::array<float, 16>& m, const Vec3& p) {
    std::array<double, 4> r{0, 0, 0, 0};
    for (int c = 0; c < 4; ++c) r[c] = p[0] * m[c] + p[1] * m[4 + c] + p[2] * m[8 + c] + m[12 + c];
    return r;
  };
  // The camera looks along +z from (1, 2, 3): the target is 10 ahead, a
  // point to the viewer's right (−x, up being +y) has positive x.
  const auto target = apply(to_camera, camera.target);
  EXPECT_NEAR(target[0], 0.0, 1e-5);
  EXPECT_NEAR(target[1], 0.0, 1e-5);
  EXPECT_NEAR(target[2], 10.0, 1e-5);
  EXPECT_GT(apply(to_camera, Vec3(0, 2, 13))[0], 0.0);
  // The top-right corner of the view lands on NDC (1, 1).
  const double half_height = std::tan(30.0 * M_PI / 180.0), half_width = half_height * 40 / 30;
  const Vec3 corner = camera.target + 10.0 * Vec3(-half_width, half_height, 0);
  const auto ndc = apply(to_ndc, corner);
  EXPECT_NEAR(ndc[0] / ndc[3], 1.0, 1e-5);
  EXPECT_NEAR(ndc[1] / ndc[3], 1.0, 1e-5);
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
