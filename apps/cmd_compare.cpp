#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "apps/commands.hpp"
#include "apps/compare_meshes.hpp"
#include "apps/options.hpp"
#include "io/output_dir.hpp"
#include "apps/tone_options.hpp"
#include "io/image_io.hpp"
#include "io/input_error.hpp"
#include "io/scene_loader.hpp"
#include "render/image_metrics.hpp"
#include "render/path_tracer.hpp"
#include "render/surface_comparison.hpp"

namespace lhr::app {

namespace {

void require_finite(const Image& image, const std::filesystem::path& path) {
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    if (!std::isfinite(image.rgb[i])) {
      const std::size_t pixel = i / 3;
      throw InputError(path, "pixel (" + std::to_string(pixel % image.width) + ", " +
                                 std::to_string(pixel / image.width) + ") is not a finite number");
    }
  }
}

}  // namespace

int run_compare(const Args& args) {
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")
      ("json", "print the metrics as JSON on stdout")
      ("diff", po::value<std::string>(),
       "write a PNG of the relative luminance error: black background, grey within 10 % (brighter with the "
       "error), yellow within 15 %, red where the image is more than 15 % too bright, blue where it is more "
       "than 15 % too dark")
      ("scene", po::value<std::string>(),
       "the scene both images show: its tone-map block applies, and background is where the camera's "
       "pixel-centre ray misses (default: where the reference is exactly 0)")
      ("surfaces", "with --scene: also the mean linear radiance of each surface over the pixels where the camera "
       "sees it, image against reference (a regional bias shows as a ratio away from 1)");
  add_tone_map_options(visible);
  po::options_description all;
  all.add(visible);
  all.add_options()("image", po::value<std::string>()->required(), "image")(
      "reference", po::value<std::string>()->required(), "reference");
  po::positional_options_description positional;
  positional.add("image", 1).add("reference", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
  if (vm.count("help")) {
    std::cout << "usage: lhr compare IMAGE.exr REFERENCE.exr [--json] [--diff DIFF.png] [--scene SCENE [--surfaces]]\n\n"
                 "Measures how close IMAGE is to REFERENCE (both linear radiance, e.g. from lhr solve\n"
                 "and lhr reference; the reference should be a converged path tracing), over the\n"
                 "non-background pixels.\n\n"
                 "Primary accuracy figure, on linear luminance Y (Rec. 709 of the linear RGB): the %\n"
                 "of pixels with |Y - Y_ref| <= 10 % (and 15 %) of max(Y_ref, 1 % of the mean Y_ref),\n"
                 "and the mean ratio mean(Y) / mean(Y_ref) (1.05: 5 % too bright overall). The\n"
                 "reference's own noise counts as error, so it should be well below 10 % (e.g.\n"
                 "lhr reference --target-noise 0.01).\n\n"
                 "Secondary, the paper's norm: the % of pixels whose display value (tone-mapped,\n"
                 "gamma) is within 10 % and 15 % of the display range of the reference's (per\n"
                 "channel: a pixel counts only if all three channels are), with RMSE and PSNR of the\n"
                 "display values and the relative error of the linear radiance. Both images go\n"
                 "through the same tone map, its defaults taken from the reference. On dim\n"
                 "tone-mapped images every method passes this norm, so it cannot rank them.\n\n"
              << visible << "\n";
    std::cout << kCompareMeshesHelp;
    return kExitOk;
  }
  po::notify(vm);
  const std::filesystem::path image_path = vm["image"].as<std::string>();
  const std::filesystem::path reference_path = vm["reference"].as<std::string>();
  if (is_mesh_file(image_path) || is_mesh_file(reference_path)) {
    if (!is_mesh_file(image_path) || !is_mesh_file(reference_path)) {
      throw po::error("compare two .ply meshes or two images, not one of each");
    }
    if (vm.count("diff") || vm.count("scene")) throw po::error("--diff and --scene apply to images, not .ply meshes");
    return compare_meshes(image_path, reference_path, vm.count("json") > 0);
  }
  std::optional<std::filesystem::path> diff_path;
  if (vm.count("diff")) {
    diff_path = vm["diff"].as<std::string>();
    if (diff_path->extension() != ".png") throw po::error("--diff must name a .png file");
    check_output_file_location(*diff_path);
  }

  const Image image = read_image(image_path);
  const Image reference = read_image(reference_path);
  require_finite(image, image_path);
  require_finite(reference, reference_path);
  if (image.width != reference.width || image.height != reference.height) {
    throw InputError(image_path, "is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                     " pixels but the reference " + reference_path.string() + " is " +
                                     std::to_string(reference.width) + "x" + std::to_string(reference.height));
  }

  if (vm.count("surfaces") && !vm.count("scene")) throw po::error("--surfaces needs --scene");
  std::vector<std::uint8_t> mask;
  ToneMapSettings tone;
  std::string background;
  std::vector<std::string> surface_names;
  std::vector<SurfaceComparison> surfaces;
  if (vm.count("scene")) {
    const std::filesystem::path scene_path = vm["scene"].as<std::string>();
    const Scene scene = load_scene(scene_path).scene;
    const Camera camera = scene.camera.value_or(framing_camera(scene));
    if (camera.width != reference.width || camera.height != reference.height) {
      throw InputError(scene_path, "its camera is " + std::to_string(camera.width) + "x" +
                                       std::to_string(camera.height) + " pixels but the images are " +
                                       std::to_string(reference.width) + "x" + std::to_string(reference.height));
    }
    tone = tone_settings_from(vm, &scene.settings.tone_map);
    const PathTracer tracer(scene);
    mask = tracer.coverage(camera);
    if (vm.count("surfaces")) {
      for (const Surface& surface : scene.surfaces) surface_names.push_back(surface.name);
      surfaces = compare_surfaces(image, reference, tracer.pixel_surfaces(camera),
                                  static_cast<int>(scene.surfaces.size()));
    }
    background = "camera rays that miss the scene";
  } else {
    tone = tone_settings_from(vm, nullptr);
    mask = nonzero_mask(reference);
    background = "reference pixels that are exactly 0";
  }
  const auto tone_map = reference_tone_map(tone, reference, mask);
  const ImageMetrics m = compare_images(image, reference, mask, *tone_map);
  if (m.pixels == 0) {
    throw InputError(reference_path, "has no non-background pixel to compare (" + background + ")");
  }
  if (diff_path) write_image(*diff_path, difference_image(image, reference, mask));

  if (vm.count("json")) {
    nlohmann::json doc;
    doc["image"] = image_path.string();
    doc["reference"] = reference_path.string();
    doc["width"] = reference.width;
    doc["height"] = reference.height;
    doc["pixels"] = m.pixels;
    doc["background_pixels"] = mask.size() - m.pixels;
    doc["background"] = background;
    doc["rel_within_10_percent"] = m.rel_within_10;
    doc["rel_within_15_percent"] = m.rel_within_15;
    doc["mean_ratio"] = finite_or_null(m.mean_ratio);
    doc["reference_mean_luminance"] = m.reference_mean_luminance;
    doc["luminance_floor"] = kLuminanceFloor * m.reference_mean_luminance;
    doc["display_within_10_percent"] = m.within_10;
    doc["display_within_15_percent"] = m.within_15;
    doc["display_rmse"] = m.rmse;
    doc["display_psnr_db"] = finite_or_null(m.psnr_db);
    doc["display_max_difference"] = m.max_difference;
    doc["relative_error"] = finite_or_null(m.relative_error);
    doc["tone_map"] = tone_map->describe();
    if (vm.count("surfaces")) {
      doc["surfaces"] = nlohmann::json::array();
      for (std::size_t i = 0; i < surfaces.size(); ++i) {
        const SurfaceComparison& c = surfaces[i];
        const Rgb ratio = c.ratio();
        doc["surfaces"].push_back({{"name", surface_names[i]},
                                   {"pixels", c.pixels},
                                   {"image", {c.image[0], c.image[1], c.image[2]}},
                                   {"reference", {c.reference[0], c.reference[1], c.reference[2]}},
                                   {"ratio", {ratio[0], ratio[1], ratio[2]}},
                                   {"luminance_ratio", c.luminance_ratio()}});
      }
    }
    std::cout << doc.dump(2) << "\n";
  } else {
    std::ostringstream s;
    s << std::fixed;
    s << "pixels compared   " << m.pixels << " of " << mask.size() << " (background: " << background << ")\n";
    s << "primary accuracy figure: linear luminance Y against the reference's\n";
    s << std::setprecision(2) << "  within 10 %     " << m.rel_within_10 << " % of pixels (|Y - Y_ref| <= 10 % of "
      << "max(Y_ref, 1 % of mean Y_ref))\n";
    s << "  within 15 %     " << m.rel_within_15 << " %\n";
    s << std::setprecision(4) << "  mean ratio      " << m.mean_ratio << " (mean Y / mean Y_ref)\n";
    s << "secondary: the paper's display-value norm (tone-mapped, gamma)\n";
    s << std::setprecision(2) << "  within 10 %     " << m.within_10 << " % of pixels (of the display range)\n";
    s << "  within 15 %     " << m.within_15 << " %\n";
    s << std::setprecision(4) << "  RMSE            " << m.rmse << " (display values in [0,1])\n";
    s << std::setprecision(2) << "  PSNR            " << m.psnr_db << " dB\n";
    s << std::setprecision(4) << "  max difference  " << m.max_difference << "\n";
    s << "relative error    " << m.relative_error << " (linear radiance, sum |a-b| / sum |b|)\n";
    s << "tone map          " << tone_map->describe() << "\n";
    if (vm.count("surfaces")) {
      s << "\nper surface: mean linear radiance, image / reference (pixels where the camera sees it)\n";
      std::size_t name_width = 24;
      for (const std::string& name : surface_names) name_width = std::max(name_width, name.size() + 2);
      const int width = static_cast<int>(name_width);
      s << std::left << std::setw(width) << "surface" << std::right << std::setw(8) << "pixels" << std::setw(11)
        << "luminance" << std::setw(9) << "red" << std::setw(9) << "green" << std::setw(9) << "blue" << "\n";
      for (std::size_t i = 0; i < surfaces.size(); ++i) {
        const SurfaceComparison& c = surfaces[i];
        if (c.pixels == 0) continue;
        const Rgb ratio = c.ratio();
        s << std::left << std::setw(width) << surface_names[i] << std::right << std::setw(8) << c.pixels
          << std::setprecision(4) << std::setw(11) << c.luminance_ratio() << std::setw(9) << ratio[0] << std::setw(9)
          << ratio[1] << std::setw(9) << ratio[2] << "\n";
      }
    }
    std::cout << s.str();
  }
  return kExitOk;
}

}  // namespace lhr::app
