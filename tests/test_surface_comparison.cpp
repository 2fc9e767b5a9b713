// Per-surface means of an image against a reference (docs/design.md §5 "How accuracy
// is judged"): the means and ratios of a constructed image whose answer is
// known, and the path tracer's per-pixel surface map against an analytic
// ray–plane intersection.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "radiosity/tone_map.hpp"
#include "io/image_io.hpp"
#include "render/camera_rays.hpp"
#include "render/path_tracer.hpp"
#include "render/surface_comparison.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

void set_pixel(Image& image, int x, int y, const Rgb& c) {
  float* p = image.pixel(x, y);
  for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(c[k]);
}

TEST(SurfaceComparison, MeansAndRatiosOfAConstructedImage) {
  // 2×2 pixels: surface 0 on the top row, surface 1 bottom left, background
  // bottom right (whatever its values, it counts for nothing).
  Image image(2, 2), reference(2, 2);
  set_pixel(reference, 0, 0, Rgb(1, 2, 4));
  set_pixel(reference, 1, 0, Rgb(3, 2, 0));
  set_pixel(image, 0, 0, Rgb(1.5, 2, 1));
  set_pixel(image, 1, 0, Rgb(4.5, 1, 1));
  set_pixel(reference, 0, 1, Rgb(1, 1, 1));
  set_pixel(image, 0, 1, Rgb(1.3, 1.3, 1.3));
  set_pixel(reference, 1, 1, Rgb(9, 9, 9));
  set_pixel(image, 1, 1, Rgb(1, 1, 1));
  const std::vector<std::int32_t> map{0, 0, 1, -1};
  const auto c = compare_surfaces(image, reference, map, 3);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].pixels, 2u);
  EXPECT_EQ(c[1].pixels, 1u);
  EXPECT_EQ(c[2].pixels, 0u);
  // Means: reference (2, 2, 2), image (3, 1.5, 1).
  EXPECT_NEAR(c[0].reference[0], 2.0, 1e-6);
  EXPECT_NEAR(c[0].image[1], 1.5, 1e-6);
  const Rgb r = c[0].ratio();
  EXPECT_NEAR(r[0], 1.5, 1e-6);
  EXPECT_NEAR(r[1], 0.75, 1e-6);
  EXPECT_NEAR(r[2], 0.5, 1e-6);
  EXPECT_NEAR(c[0].luminance_ratio(), luminance(Rgb(3, 1.5, 1)) / 2.0, 1e-6);
  EXPECT_NEAR(c[1].luminance_ratio(), 1.3, 1e-6);
  EXPECT_EQ(c[2].luminance_ratio(), 0.0);
}

TEST(SurfaceComparison, RejectsMismatchedSizesAndUnknownSurfaces) {
  const Image a(2, 2), b(2, 1);
  EXPECT_THROW(compare_surfaces(a, b, {0, 0}, 1), std::invalid_argument);
  EXPECT_THROW(compare_surfaces(a, a, {0, 0, 0}, 1), std::invalid_argument);
  EXPECT_THROW(compare_surfaces(a, a, {0, 0, 0, 2}, 2), std::invalid_argument);
}

TEST(SurfaceComparison, PathTracerNamesTheSurfaceEachPixelSees) {
  // Two unit squares side by side in z = 0, facing +z, in two groups: the
  // left one (x < 0) and the right one; the camera above sees background
  // beyond |y| = 0.5.
  PolygonSoup soup;
  Material m;
  m.name = "grey";
  soup.materials = {m};
  soup.groups = {"left", "right"};
  test::add_quad(soup, Vec3(-1, -0.5, 0), Vec3(0, -0.5, 0), Vec3(0, 0.5, 0), Vec3(-1, 0.5, 0), 0, 0);
  test::add_quad(soup, Vec3(0, -0.5, 0), Vec3(1, -0.5, 0), Vec3(1, 0.5, 0), Vec3(0, 0.5, 0), 0, 1);
  const Scene scene = test::scene_from_soup(soup, "two squares");
  ASSERT_EQ(scene.surfaces.size(), 2u);
  const int left = scene.surfaces[0].name.rfind("left", 0) == 0 ? 0 : 1;
  Camera camera;
  camera.eye = Vec3(0.1, 0.05, 2);
  camera.target = Vec3(0.1, 0.05, 0);
  camera.fov_y_deg = 60.0;
  camera.width = 48;
  camera.height = 40;
  const auto map = PathTracer(scene).pixel_surfaces(camera);
  ASSERT_EQ(map.size(), 48u * 40u);
  const CameraRays rays(camera);
  int seen[2] = {0, 0}, background = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const Vec3 d = rays.direction(x, y);
      const Vec3 p = rays.origin() - rays.origin()[2] / d[2] * d;
      // Rays within a hair of an edge could go either way.
      if (std::abs(p[0]) < 1e-3 || std::abs(std::abs(p[0]) - 1) < 1e-3 || std::abs(std::abs(p[1]) - 0.5) < 1e-3) {
        continue;
      }
      const bool on = std::abs(p[0]) < 1 && std::abs(p[1]) < 0.5;
      const int expected = !on ? -1 : (p[0] < 0 ? left : 1 - left);
      EXPECT_EQ(map[static_cast<std::size_t>(y) * camera.width + x], expected) << "pixel " << x << ", " << y;
      if (expected < 0) {
        ++background;
      } else {
        ++seen[expected];
      }
    }
  }
  EXPECT_GT(seen[0], 100);
  EXPECT_GT(seen[1], 100);
  EXPECT_GT(background, 100);
}

TEST(SurfaceComparison, CompareCommandReportsEachSurfacesRatio) {
  // A floor and a light seen from the side; an image 1.5 times the reference
  // on every pixel is 1.5 times it on every surface seen.
  const auto dir = test::fresh_dir("compare_surfaces");
  test::write_text(dir / "two.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nKe 0 0 0\nnewmtl light\nKd 0 0 0\nKe 1 1 1\n");
  test::write_text(dir / "two.obj",
                   "mtllib two.mtl\n"
                   "g floor\nusemtl floor\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                   "g light\nusemtl light\nv 0.2 0.2 0.5\nv 0.2 0.8 0.5\nv 0.8 0.8 0.5\nv 0.8 0.2 0.5\nf 5 6 7 8\n");
  const auto scene = dir / "two.scene.json";
  test::write_text(scene, "{\"mesh\": \"two.obj\", \"camera\": {\"eye\": [0.5, -0.3, 0.3], \"target\": [0.5, 0.5, "
                          "0.15], \"up\": [0, 0, 1], \"fov_y_deg\": 90, \"width\": 20, \"height\": 16}}\n");
  Image reference(20, 16), image(20, 16);
  for (std::size_t i = 0; i < reference.rgb.size(); ++i) {
    // Values a half-float EXR holds exactly, times 1.5 too.
    reference.rgb[i] = 0.25f * static_cast<float>(1 + i % 4);
    image.rgb[i] = 1.5f * reference.rgb[i];
  }
  write_image(dir / "ref.exr", reference);
  write_image(dir / "image.exr", image);
  auto r = test::run_lhr({"compare", (dir / "image.exr").string(), (dir / "ref.exr").string(), "--scene",
                          scene.string(), "--surfaces", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["surfaces"].size(), 2u);
  std::size_t seen = 0;
  for (const auto& surface : doc["surfaces"]) {
    EXPECT_GT(surface["pixels"].get<int>(), 0) << surface["name"];
    seen += surface["pixels"].get<std::size_t>();
    EXPECT_NEAR(surface["luminance_ratio"].get<double>(), 1.5, 1e-5) << surface["name"];
  }
  EXPECT_EQ(seen, doc["pixels"].get<std::size_t>());
  r = test::run_lhr({"compare", (dir / "image.exr").string(), (dir / "ref.exr").string(), "--scene", scene.string(),
                     "--surfaces"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("light"), std::string::npos) << r.out;
  // Surfaces need the scene that says which pixel shows which.
  r = test::run_lhr({"compare", (dir / "image.exr").string(), (dir / "ref.exr").string(), "--surfaces"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--scene"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace lhr
