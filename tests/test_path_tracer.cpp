// The path-traced reference (docs/design.md §5) against closed forms: the furnace
// (radiance Ke/(1−ρ) everywhere) and a receiver lit by one emitter (radiance
// ρ·Ke·F(x) with the exact point-to-polygon form factor), both within the
// noise the tracer reports; determinism; and `lhr reference` / `lhr compare`
// end to end.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>

#include "io/image_io.hpp"
#include "radiosity/form_factor.hpp"
#include "radiosity/tone_map.hpp"
#include "render/camera_rays.hpp"
#include "render/path_tracer.hpp"
#include "scene_fixtures.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

// A camera in the middle of the unit cube, looking at a wall.
Camera camera_inside_cube(int size) {
  Camera c;
  c.eye = Vec3(0.5, 0.5, 0.5);
  c.target = Vec3(0.5, 0.5, 0.0);
  c.up = Vec3(0, 1, 0);
  c.fov_y_deg = 100.0;
  c.width = c.height = size;
  return c;
}

// Pixels of a render set against their true luminance: each pixel's error
// over its own reported standard error is a z-score.
struct Agreement {
  int pixels = 0;
  double rms_z = 0, max_abs_z = 0;
  double mean_error = 0, max_abs_error = 0;  // luminance
  double rms_standard_error = 0;
};

Agreement agreement(const ReferenceImage& r, const std::vector<std::optional<double>>& truth) {
  Agreement a;
  double sum_z2 = 0, sum_e = 0, sum_se2 = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (!truth[i]) continue;
    const float* p = &r.radiance.rgb[3 * i];
    const double error = luminance(Rgb(p[0], p[1], p[2])) - *truth[i];
    const double se = r.standard_error[i];
    EXPECT_GT(se, 0.0) << "pixel " << i;
    const double z = error / se;
    sum_z2 += z * z;
    sum_e += error;
    sum_se2 += se * se;
    a.max_abs_z = std::max(a.max_abs_z, std::abs(z));
    a.max_abs_error = std::max(a.max_abs_error, std::abs(error));
    ++a.pixels;
  }
  if (a.pixels == 0) return a;
  a.rms_z = std::sqrt(sum_z2 / a.pixels);
  a.mean_error = sum_e / a.pixels;
  a.rms_standard_error = std::sqrt(sum_se2 / a.pixels);
  return a;
}

// RMS of the per-pixel standard errors over the pixels the noise covers.
double rms_standard_error(const ReferenceImage& r) {
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < r.mask.size(); ++i) {
    if (!r.mask[i]) continue;
    sum += static_cast<double>(r.standard_error[i]) * r.standard_error[i];
    ++n;
  }
  return n ? std::sqrt(sum / n) : 0.0;
}

// Pixels are independent, so with P of them an unbiased render with honest
// standard errors has: a mean error within 3× the RMS standard error over
// √P; z-scores of RMS near 1 (its own spread is about 1/√(2P)); and every
// pixel within 3 standard errors but for the odd tail pixel, none beyond
// 5.5 (for Gaussian errors that happens once in ~10⁵ renders of a few
// hundred pixels; these errors are a little skewed). Where every pixel has
// the same noise (the furnace), the image's reported RMS noise bounds each
// pixel's error too.
void expect_within_reported_noise(const ReferenceImage& r, const Agreement& a, bool same_noise_everywhere) {
  SCOPED_TRACE(testing::Message() << a.pixels << " pixels, RMS z " << a.rms_z << ", max |z| " << a.max_abs_z
                                  << ", mean error " << a.mean_error << ", RMS standard error "
                                  << a.rms_standard_error << ", reported noise " << r.noise_rms);
  ASSERT_GT(a.pixels, 100);
  const double root_p = std::sqrt(static_cast<double>(a.pixels));
  EXPECT_LT(std::abs(a.mean_error), 3.0 * a.rms_standard_error / root_p);
  EXPECT_GT(a.rms_z, 0.8);
  EXPECT_LT(a.rms_z, 1.25);
  EXPECT_LT(a.max_abs_z, 5.5);
  if (same_noise_everywhere) {
    EXPECT_LT(a.max_abs_error, 5.5 * r.noise_rms);
  }
  // The half-image noise and the per-pixel sample variances estimate the
  // same standard errors.
  EXPECT_GT(r.noise_rms, 0.8 * rms_standard_error(r));
  EXPECT_LT(r.noise_rms, 1.25 * rms_standard_error(r));
}

TEST(PathTracer, FurnaceConvergesToEmissionOverOneMinusReflectance) {
  const Scene scene = test::furnace_cube(0.5, 1.0);
  const PathTracer tracer(scene);
  PathTraceOptions options;
  options.spp = 256;
  options.jitter = true;
  const ReferenceImage r = tracer.render(camera_inside_cube(16), options);
  EXPECT_EQ(r.spp, 256);
  // Every pixel sees a wall: no background.
  EXPECT_EQ(std::count(r.mask.begin(), r.mask.end(), 1), 256);
  const double truth = luminance(Rgb(2, 2, 2));  // Ke/(1−ρ) = 2 in every channel
  const Agreement a = agreement(r, std::vector<std::optional<double>>(r.mask.size(), truth));
  expect_within_reported_noise(r, a, true);
  EXPECT_NEAR(r.mean_luminance, truth, 3.0 * r.noise_rms);
  EXPECT_NEAR(r.noise, r.noise_rms / r.mean_luminance, 1e-12);
}

TEST(PathTracer, ColouredFurnaceConvergesPerChannel) {
  // Russian roulette follows the largest channel; each channel must still
  // converge to its own Ke/(1−ρ).
  Material m;
  m.name = "coloured furnace";
  m.reflectance = Rgb(0.8, 0.3, 0.55);
  m.emission = Rgb(0.2, 1.4, 0.9);
  const Scene scene = test::closed_cube(m, m, "coloured furnace");
  const Rgb truth(0.2 / 0.2, 1.4 / 0.7, 0.9 / 0.45);
  const PathTracer tracer(scene);
  PathTraceOptions options;
  options.spp = 256;
  const ReferenceImage r = tracer.render(camera_inside_cube(16), options);
  const Agreement a = agreement(r, std::vector<std::optional<double>>(r.mask.size(), luminance(truth)));
  expect_within_reported_noise(r, a, true);
  // Per channel: every pixel draws from the same distribution here, so the
  // spread of the pixels gives the standard error of their mean.
  const double n = static_cast<double>(r.mask.size());
  for (int c = 0; c < 3; ++c) {
    double sum = 0, sum2 = 0;
    for (std::size_t i = 0; i < r.mask.size(); ++i) {
      sum += r.radiance.rgb[3 * i + c];
      sum2 += static_cast<double>(r.radiance.rgb[3 * i + c]) * r.radiance.rgb[3 * i + c];
    }
    const double mean = sum / n;
    const double standard_error = std::sqrt((sum2 / n - mean * mean) / (n - 1));
    EXPECT_NEAR(mean, truth[c], 4.0 * standard_error) << "channel " << c;
  }
}

// The emitter-over-receiver case seen from below the emitter's plane, so the
// camera sees the receiver (lit only by the emitter, whose Kd is 0) and the
// emitter's front, and beyond them nothing.
struct LitReceiver {
  static constexpr double kSize = 0.6, kHeight = 0.5, kRho = 0.7, kKe = 3.0;
  Scene scene = test::emitter_over_receiver(kSize, kHeight, kRho, kKe);
  Camera camera;
  LitReceiver() {
    camera.eye = Vec3(0.5, -0.3, 0.3);
    camera.target = Vec3(0.5, 0.5, 0.15);
    camera.up = Vec3(0, 0, 1);
    camera.fov_y_deg = 90.0;
    camera.width = 40;
    camera.height = 30;
  }
  std::array<Vec3, 4> emitter() const {
    const double lo = 0.5 - kSize / 2, hi = 0.5 + kSize / 2;
    return {Vec3(lo, lo, kHeight), Vec3(lo, hi, kHeight), Vec3(hi, hi, kHeight), Vec3(hi, lo, kHeight)};
  }
};

// Where the pixel-centre ray meets the plane z = h inside [lo, hi]², if it does.
std::optional<Vec3> plane_hit(const Vec3& eye, const Vec3& d, double h, double lo, double hi) {
  if (std::abs(d[2]) < 1e-12) return std::nullopt;
  const double t = (h - eye[2]) / d[2];
  if (t <= 0) return std::nullopt;
  const Vec3 p = eye + t * d;
  if (p[0] <= lo || p[0] >= hi || p[1] <= lo || p[1] >= hi) return std::nullopt;
  return p;
}

TEST(PathTracer, ReceiverUnderAnEmitterMatchesTheFormFactor) {
  const LitReceiver setup;
  const PathTracer tracer(setup.scene);
  PathTraceOptions options;
  options.spp = 128;
  const ReferenceImage r = tracer.render(setup.camera, options);
  const CameraRays rays(setup.camera);
  const auto emitter = setup.emitter();
  const double lo = 0.5 - LitReceiver::kSize / 2, hi = 0.5 + LitReceiver::kSize / 2;
  std::vector<std::optional<double>> truth(r.mask.size());
  int emitter_pixels = 0, background = 0;
  for (int y = 0; y < setup.camera.height; ++y) {
    for (int x = 0; x < setup.camera.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * setup.camera.width + x;
      const Vec3 d = rays.direction(x, y);
      const float* p = &r.radiance.rgb[3 * i];
      // Keep a margin from the squares' edges, where float rays may land on either side.
      if (plane_hit(rays.origin(), d, LitReceiver::kHeight, lo + 1e-4, hi - 1e-4)) {
        // The emitter's front, Kd 0: exactly Ke, nothing reflected.
        EXPECT_TRUE(r.mask[i]);
        for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], static_cast<float>(LitReceiver::kKe));
        ++emitter_pixels;
      } else if (const auto x0 = plane_hit(rays.origin(), d, 0.0, 1e-4, 1 - 1e-4)) {
        EXPECT_TRUE(r.mask[i]);
        const Vec3 up(0, 0, 1);
        const double f = point_polygon_form_factor(*x0, up, std::span<const Vec3>(emitter.data(), emitter.size()));
        truth[i] = luminance(Rgb(1, 1, 1) * (LitReceiver::kRho * LitReceiver::kKe * f));
      } else if (!plane_hit(rays.origin(), d, LitReceiver::kHeight, lo - 1e-4, hi + 1e-4) &&
                 !plane_hit(rays.origin(), d, 0.0, -1e-4, 1 + 1e-4)) {
        // Nothing there: background, black and marked.
        EXPECT_FALSE(r.mask[i]);
        for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], 0.0f);
        ++background;
      }
    }
  }
  EXPECT_GT(emitter_pixels, 20);
  EXPECT_GT(background, 20);
  const Agreement a = agreement(r, truth);
  expect_within_reported_noise(r, a, false);
}

TEST(PathTracer, SameImageWhateverTheThreadCount) {
  const LitReceiver setup;
  const PathTracer tracer(setup.scene);
  PathTraceOptions options;
  options.spp = 16;
  options.jitter = true;
  options.seed = 7;
  const auto render_with = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return tracer.render(setup.camera, options);
  };
  const ReferenceImage one = render_with(1), two = render_with(2);
  EXPECT_EQ(one.radiance.rgb, two.radiance.rgb);
  EXPECT_EQ(one.standard_error, two.standard_error);
  EXPECT_EQ(one.mask, two.mask);
  EXPECT_EQ(one.noise, two.noise);
  // Another seed is another image.
  options.seed = 8;
  EXPECT_NE(tracer.render(setup.camera, options).radiance.rgb, one.radiance.rgb);
}

TEST(PathTracer, RoundsAddSamplesToTheSameImage) {
  const LitReceiver setup;
  const PathTracer tracer(setup.scene);
  PathTraceOptions direct;
  direct.spp = 32;
  direct.jitter = true;
  const ReferenceImage once = tracer.render(setup.camera, direct);
  // An unreachable target: doubling 8 → 16 → 32 stops at the limit.
  PathTraceOptions rounds = direct;
  rounds.spp = 8;
  rounds.target_noise = 1e-9;
  rounds.max_spp = 32;
  const ReferenceImage doubled = tracer.render(setup.camera, rounds);
  EXPECT_EQ(doubled.spp, 32);
  EXPECT_EQ(doubled.rounds, 3);
  EXPECT_EQ(doubled.radiance.rgb, once.radiance.rgb);
  EXPECT_EQ(doubled.noise, once.noise);
  // A reachable target ends the rounds as soon as the noise is below it.
  rounds.target_noise = once.noise;
  rounds.max_spp = 4096;
  const ReferenceImage reached = tracer.render(setup.camera, rounds);
  EXPECT_LE(reached.noise, rounds.target_noise);
  EXPECT_LE(reached.spp, 4096);
}

TEST(PathTracer, NonConvexPolygonsAreCoveredExactly) {
  // An L-shaped floor listed from a vertex next to the notch, so a fan from
  // its first vertex would cover the notch: it must be ear-clipped.
  PolygonSoup soup;
  Material m;
  m.name = "floor";
  soup.materials = {m};
  soup.groups = {"floor"};
  soup.points = {Vec3(2, 1, 0), Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0), Vec3(0, 0, 0), Vec3(2, 0, 0)};
  soup.faces.push_back({{0, 1, 2, 3, 4, 5}, 0, 0, 0});
  const PathTracer tracer(test::scene_from_soup(soup, "L"));
  EXPECT_EQ(tracer.triangle_count(), 4u);
  Camera camera;
  camera.eye = Vec3(1, 1, 5);
  camera.target = Vec3(1, 1, 0);
  camera.up = Vec3(0, 1, 0);
  camera.fov_y_deg = 30;
  camera.width = camera.height = 32;
  const auto mask = tracer.coverage(camera);
  const CameraRays rays(camera);
  int inside = 0, notch = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const Vec3 d = rays.direction(x, y);
      const Vec3 p = rays.origin() + (-rays.origin()[2] / d[2]) * d;
      const auto near = [](double v, double edge) { return std::abs(v - edge) < 1e-3; };
      if (near(p[0], 0) || near(p[0], 1) || near(p[0], 2) || near(p[1], 0) || near(p[1], 1) || near(p[1], 2)) continue;
      const bool in_square = p[0] > 0 && p[0] < 2 && p[1] > 0 && p[1] < 2;
      const bool in_notch = p[0] > 1 && p[1] > 1;
      EXPECT_EQ(mask[static_cast<std::size_t>(y) * camera.width + x], in_square && !in_notch ? 1 : 0) << x << "," << y;
      inside += in_square && !in_notch;
      notch += in_square && in_notch;
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(notch, 50);
}

TEST(PathTracer, RejectsTooFewSamples) {
  const PathTracer tracer(test::furnace_cube(0.5, 1.0));
  PathTraceOptions options;
  options.spp = 1;
  EXPECT_THROW(tracer.render(camera_inside_cube(4), options), std::invalid_argument);
}

// A tiny scene on disk: the lit receiver as OBJ, MTL and scene JSON.
std::filesystem::path write_tiny_scene(const std::filesystem::path& dir, int width, int height) {
  test::write_lit_floor_obj(dir);
  const auto path = dir / ("tiny_" + std::to_string(width) + ".scene.json");
  test::write_text(path, "{\"mesh\": \"tiny.obj\", \"camera\": {\"eye\": [0.5, -0.3, 0.3], \"target\": [0.5, 0.5, "
                         "0.15], \"up\": [0, 0, 1], \"fov_y_deg\": 90, \"width\": " +
                             std::to_string(width) + ", \"height\": " + std::to_string(height) + "}}\n");
  return path;
}

TEST(ReferenceCommand, WritesTheImagesAndCompareMeasuresThem) {
  const auto dir = test::fresh_dir("reference_command");
  const auto scene = write_tiny_scene(dir, 24, 16);
  const auto ref = (dir / "out" / "ref.exr").string();
  auto r = test::run_lhr({"reference", scene.string(), "--spp", "8", "--out", ref, "--png",
                          (dir / "out" / "ref.png").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const Image exr = read_image(ref);
  EXPECT_EQ(exr.width, 24);
  EXPECT_EQ(exr.height, 16);
  const Image png = read_image(dir / "out" / "ref.png");
  EXPECT_EQ(png.width, 24);
  // Without --quiet it reports the noise.
  r = test::run_lhr({"reference", scene.string(), "--spp", "8", "--seed", "2", "--out", (dir / "other.exr").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("noise"), std::string::npos) << r.err;

  // An image against itself agrees everywhere.
  r = test::run_lhr({"compare", ref, ref, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto doc = nlohmann::json::parse(r.out);
  for (const char* key : {"rel_within_10_percent", "rel_within_15_percent", "display_within_10_percent",
                          "display_within_15_percent"}) {
    EXPECT_EQ(doc[key].get<double>(), 100.0) << key;
  }
  EXPECT_EQ(doc["mean_ratio"].get<double>(), 1.0);
  EXPECT_EQ(doc["display_rmse"].get<double>(), 0.0);
  EXPECT_TRUE(doc["display_psnr_db"].is_null());
  // Two seeds differ by their noise; with the scene, background is where the camera misses.
  r = test::run_lhr({"compare", (dir / "other.exr").string(), ref, "--json", "--scene", scene.string(), "--diff",
                     (dir / "diff.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  doc = nlohmann::json::parse(r.out);
  for (const char* key : {"rel_within_10_percent", "rel_within_15_percent", "display_within_10_percent",
                          "display_within_15_percent"}) {
    EXPECT_GE(doc[key].get<double>(), 0.0) << key;
    EXPECT_LE(doc[key].get<double>(), 100.0) << key;
  }
  // Independent samples of the same radiance: no bias beyond their noise.
  EXPECT_NEAR(doc["mean_ratio"].get<double>(), 1.0, 0.1);
  EXPECT_GT(doc["display_rmse"].get<double>(), 0.0);
  EXPECT_GT(doc["background_pixels"].get<int>(), 0);
  EXPECT_EQ(doc["pixels"].get<int>() + doc["background_pixels"].get<int>(), 24 * 16);
  EXPECT_TRUE(std::filesystem::exists(dir / "diff.png"));
  // Text output names the norms, the relative luminance one first as the primary figure.
  r = test::run_lhr({"compare", (dir / "other.exr").string(), ref});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto primary = r.out.find("primary accuracy figure: linear luminance");
  const auto secondary = r.out.find("secondary: the paper's display-value norm");
  EXPECT_NE(primary, std::string::npos) << r.out;
  EXPECT_NE(secondary, std::string::npos) << r.out;
  EXPECT_LT(primary, secondary) << r.out;
  EXPECT_NE(r.out.find("mean ratio"), std::string::npos) << r.out;
}

TEST(ReferenceCommand, BadInputGivesOneLineNamingTheProblem) {
  const auto dir = test::fresh_dir("reference_bad_input");
  const auto small = write_tiny_scene(dir, 8, 6);
  const auto large = write_tiny_scene(dir, 10, 6);
  ASSERT_EQ(test::run_lhr({"reference", small.string(), "--spp", "4", "--out", (dir / "a.exr").string(), "-q"})
                .exit_code,
            0);
  ASSERT_EQ(test::run_lhr({"reference", large.string(), "--spp", "4", "--out", (dir / "b.exr").string(), "-q"})
                .exit_code,
            0);
  const auto missing = (dir / "missing.exr").string();
  auto r = test::run_lhr({"compare", missing, (dir / "a.exr").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("missing.exr"), std::string::npos) << r.err;
  r = test::run_lhr({"compare", (dir / "b.exr").string(), (dir / "a.exr").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("10x6"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("8x6"), std::string::npos) << r.err;
  r = test::run_lhr({"compare", (dir / "a.exr").string(), (dir / "a.exr").string(), "--scene", large.string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"reference", small.string(), "--spp", "1", "--out", (dir / "c.exr").string()},
        std::vector<std::string>{"reference", small.string(), "--out", (dir / "c.png").string()},
        std::vector<std::string>{"compare", (dir / "a.exr").string()}}) {
    r = test::run_lhr(args);
    EXPECT_EQ(r.exit_code, 2) << args[1];
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  }
  r = test::run_lhr({"reference", (dir / "nothing.scene.json").string(), "--out", (dir / "c.exr").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nothing.scene.json"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace lhr
