#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>

#include <tbb/global_control.h>

#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/options.hpp"
#include "apps/tone_options.hpp"
#include "io/image_io.hpp"
#include "io/json_file.hpp"
#include "io/mesh_io.hpp"
#include "io/output_dir.hpp"
#include "io/scene_loader.hpp"
#include "radiosity/memory_budget.hpp"
#include "render/solution.hpp"

namespace lhr::app {

namespace {

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

}  // namespace

int run_solve(const Args& args) {
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")
      ("out,o", po::value<std::string>()->required(),
       "output directory (created if missing): mesh.ply, mesh.off, image.png, image.exr, stats.json")
      ("method", po::value<std::string>()->default_value("linear"),
       "solver: linear (the paper's linear hierarchical radiosity with the image-space refinement criterion) "
       "or classical (Hanrahan et al. 1991, constant elements, BF refinement)")
      ("eps-pixel", double_value(LinearOptions{}.eps_pixel),
       "linear: split a receiver edge when its display error times the pixels it covers reaches this (paper 4.1). "
       "Display values run from 0 (black) to 1 (the display's white), so 1 is the whole range over one pixel, or "
       "one 8-bit grey level (1/255) over 255 pixels; the default 0.3 is one grey level over about 77 pixels")
      ("eps-link", double_value(LinearOptions{}.eps_link),
       "linear: refine a link when its reflected contribution, relative to the adaptation luminance, times the "
       "pixels of the receiving node reaches this (paper 4.2), or when the error of its shooter element's values, "
       "summed over the pixels of every node linked to that element, does")
      ("eps-vertex", double_value(LinearOptions{}.eps_vertex),
       "linear: also refine a link when its shooter element's error reaching a node (form factor x the spread "
       "of the element's values, reflected) exceeds this fraction of the node's radiance, wherever the camera "
       "looks: the exported mesh's values near corners and contacts (0: off)")
      ("eps-power", double_value(LinearOptions{}.eps_power),
       "linear: also split a receiver edge, wherever the camera looks, when the reflected power its linear "
       "interpolant misplaces reaches this fraction of the power the lights emit: the exported mesh's accuracy "
       "in object space (smaller brings each surface's mean closer to the truth, at more elements)")
      ("redraw-cluster-links",
       "linear: draw every link from a cluster of initial triangles again in every iteration, from the radiance "
       "its shooter then holds, not only when it is made: takes out the excess that shape factors made from the "
       "direct light keep (docs/accuracy.md, \"A shape factor that ages\"); for measuring: about four times the "
       "solve's time, and k^2 rays for every cluster link")
      ("rescale-cluster-links",
       "linear: rescale every link from a cluster of initial triangles, without new rays, once its shooter's "
       "radiance has changed shape by 1 % since its shape factor was made: takes out the same excess as "
       "--redraw-cluster-links for a small part of its cost (docs/accuracy.md, \"A shape factor that ages\"); "
       "off by default until the losses it uncovers are fixed")
      ("vis-threshold", double_value(LinearOptions{}.vis_threshold),
       "linear: a visibility difference along an edge at least this large makes the receiver oracle conservative")
      ("link-power", double_value(LinearOptions{}.link_power),
       "linear: surfaces start shooting brightest first, until those left out carry together less than this "
       "fraction of the emitted power")
      ("eps-bf", double_value(ClassicalOptions{}.eps_bf),
       "classical: refine a link while shooter radiance x form factor, or the spread of the shooter's leaves "
       "about its value x form factor, exceeds this fraction of the brightest emitted radiance; and split a "
       "shooter for all its receivers while what its spread may misplace over all of them together exceeds "
       "this fraction of the emitted power")
      ("min-edge", po::value<double>(),
       "smallest element edge (default h/32, finer toward a small surface and on a thin one: docs/design.md, "
       "\"Limits the user controls\")")
      ("max-iterations", po::value<int>(), "iteration limit (default: linear 50, classical 100)")
      ("tolerance", po::value<double>(),
       "stop when no value changes by more than this fraction of itself (at least 1 % of the adaptation "
       "luminance; classical: of the scene's log-average), so a dim wall beside a bright lamp has converged "
       "too (default 1e-4)")
      ("max-links", po::value<std::size_t>()->default_value(0), "stop refining at this many links (0: no limit)")
      ("max-memory", po::value<std::string>()->default_value("auto"),
       "stop refining before the radiosity data (hierarchies, values, graphs, links: stats.json bytes.total) "
       "passes this size, e.g. 512M or 2G; auto: a quarter of this machine's memory (or of its control "
       "group's limit); 0: no limit. The process adds the scene, its ray-tracing structure, the libraries "
       "and about 64 bytes per image pixel; a camera whose image does not fit beside the budget is refused "
       "(docs/robustness.md)")
      ("visibility-samples", po::value<int>()->default_value(ClassicalOptions{}.visibility_samples),
       "k: k^2 shadow rays per link; linear: at least that, and up to (4k)^2 for a partly hidden link that "
       "brings much of its node's value (docs/design.md, \"How many rays\")")
      ("tone-map", po::value<std::string>()->default_value("tumblin-rushmeier"),
       "tumblin-rushmeier (paper ref. 18) or linear; the tone flags override the scene file's "
       "\"tone_map\" block, which overrides these defaults")
      ("adaptation", double_value(0.0),
       "world adaptation luminance for tumblin-rushmeier, scene units (0: log-average the camera sees)")
      ("units-to-cd", double_value(1.0), "cd/m^2 per scene radiance unit")
      ("white", double_value(0.0), "linear tone map: luminance shown as white (0: brightest seen)")
      ("display-max", double_value(100.0), "tumblin-rushmeier: display's maximum luminance, cd/m^2")
      ("max-contrast", double_value(100.0), "tumblin-rushmeier: display's maximum contrast")
      ("gamma", double_value(2.2), "display gamma")
      ("threads", po::value<int>()->default_value(0), "worker threads (0: all cores); results do not depend on it")
      ("quiet,q", "print nothing but errors")
      ("verbose,v", "print every iteration");
  add_scene_meshing_options(visible);
  po::variables_map vm;
  if (!parse_command_line(args,
                          "usage: lhr solve SCENE --out DIR [options]\n\n"
                          "Computes diffuse global illumination for SCENE (.scene.json, .obj, .ply, .off)\n"
                          "and writes the lit, refined mesh, a Gouraud view from the scene camera and the\n"
                          "solver's statistics.",
                          visible, Positional{"scene"}, vm)) {
    return kExitOk;
  }
  const bool quiet = vm.count("quiet") > 0;
  const bool verbose = vm.count("verbose") > 0 && !quiet;
  const bool progress = !quiet && ::isatty(STDERR_FILENO);
  const std::string method = vm["method"].as<std::string>();
  if (method != "linear" && method != "classical") throw po::error("--method must be linear or classical");
  const int threads = vm["threads"].as<int>();
  if (threads < 0) throw po::error("--threads must be 0 or positive");
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism,
                                   threads > 0 ? static_cast<std::size_t>(threads)
                                               : tbb::global_control::active_value(
                                                     tbb::global_control::max_allowed_parallelism));

  install_interrupt_handlers();
  const std::filesystem::path out_dir = vm["out"].as<std::string>();
  const auto t_start = Clock::now();
  SolveSettings settings;
  settings.method = method == "linear" ? SolveMethod::kLinear : SolveMethod::kClassical;
  ClassicalOptions& classical = settings.classical;
  LinearOptions& linear = settings.linear;
  const double min_edge = vm.count("min-edge") ? vm["min-edge"].as<double>() : 0.0;
  const int max_iterations = vm.count("max-iterations") ? vm["max-iterations"].as<int>()
                             : method == "linear"        ? linear.max_iterations
                                                         : classical.max_iterations;
  const double tolerance = vm.count("tolerance") ? vm["tolerance"].as<double>()
                           : method == "linear"    ? linear.tolerance
                                                   : classical.tolerance;
  const std::size_t max_links = vm["max-links"].as<std::size_t>();
  const int visibility_samples = vm["visibility-samples"].as<int>();
  classical.eps_bf = vm["eps-bf"].as<double>();
  linear.eps_pixel = vm["eps-pixel"].as<double>();
  linear.eps_link = vm["eps-link"].as<double>();
  linear.vis_threshold = vm["vis-threshold"].as<double>();
  linear.eps_vertex = vm["eps-vertex"].as<double>();
  linear.eps_power = vm["eps-power"].as<double>();
  linear.redraw_cluster_links = vm.count("redraw-cluster-links") > 0;
  linear.rescale_cluster_links = vm.count("rescale-cluster-links") > 0;
  linear.link_power = vm["link-power"].as<double>();
  classical.min_edge = linear.min_edge = min_edge;
  classical.max_iterations = linear.max_iterations = max_iterations;
  classical.tolerance = linear.tolerance = tolerance;
  classical.max_links = linear.max_links = max_links;
  const std::string max_memory = vm["max-memory"].as<std::string>();
  const bool default_budget = max_memory == "auto";
  classical.max_bytes = linear.max_bytes =
      default_budget ? default_memory_budget() : parse_byte_size(max_memory, "--max-memory");
  classical.visibility_samples = linear.visibility_samples = visibility_samples;
  try {
    check_solver_options(settings, OptionStyle::kFlag);
  } catch (const std::invalid_argument& e) {
    throw po::error(e.what());
  }

  // Options are checked before the scene is read: a bad flag is the one line
  // of output, not a scene's warnings and then the flag.
  const LoadResult loaded = load_scene(vm["scene"].as<std::string>(), load_options_from(vm));
  const Scene& scene = loaded.scene;
  const Camera camera = scene.camera.value_or(framing_camera(scene));
  settings.camera = camera;
  settings.meshing = meshing_options_from(vm, scene);
  try {
    check_image_budget(settings, OptionStyle::kFlag);
  } catch (const std::invalid_argument& e) {
    throw po::error(e.what());
  }
  // After the checks that need the scene, so that a refusal is one line too.
  if (!quiet) {
    for (const std::string& w : loaded.warnings) std::cerr << "lhr solve: warning: " << w << "\n";
  }

  // Refuse an unusable output directory before the work, not after, and hold
  // it until the outputs are published: two solves into one directory would
  // otherwise interleave their files into a mixed set (docs/robustness.md).
  prepare_output_directory(out_dir);
  const OutputDirectoryLock out_lock(out_dir);

  if (!quiet) {
    for (const std::string& w : scene_warnings(scene)) std::cerr << "lhr solve: warning: " << w << "\n";
    if (default_budget && linear.max_bytes > 0) {
      std::cerr << "lhr solve: memory budget " << format_bytes(linear.max_bytes) << " for the radiosity data (a quarter of "
                << format_bytes(machine_memory_bytes()) << "; --max-memory sets it)\n";
    }
  }

  // The tone map shapes the linear method's receiver oracle (paper §4.1) as
  // well as the images and vertex colours.
  settings.tone = tone_settings_from(vm, &scene.settings.tone_map);

  const auto report = [&](int iteration, double change) {
    throw_if_interrupted();
    if (verbose) {
      std::cerr << "iteration " << iteration << ": largest change " << change << "\n";
    } else if (progress) {
      std::cerr << "\riteration " << iteration << ": largest change " << change << "   " << std::flush;
    }
  };
  settings.linear.checkpoint = settings.classical.checkpoint = throw_if_interrupted;
  Solution solution;
  try {
    solution = solve_scene(scene, settings, report);
  } catch (const Interrupted& e) {
    if (progress && !verbose) std::cerr << "\n";
    std::cerr << "lhr solve: " << e.what() << "\n";
    return kExitInterrupted;
  }
  if (progress && !verbose) std::cerr << "\n";
  if (!quiet) {
    for (const std::string& w : solution_warnings(settings, solution, OptionStyle::kFlag)) {
      std::cerr << "lhr solve: warning: " << w << "\n";
    }
  }

  const auto t_output = Clock::now();
  SolutionView& view = solution.view;
  nlohmann::json doc = solution.stats;
  doc["lhr_version"] = LHR_VERSION;
  // Every file is complete on disk before any replaces an earlier one; an
  // interrupt or a failed write until then leaves the earlier set whole.
  try {
    AtomicOutputs outputs;
    write_mesh(outputs, out_dir / "mesh.ply", view.export_mesh);
    throw_if_interrupted();
    write_mesh(outputs, out_dir / "mesh.off", view.export_mesh);
    throw_if_interrupted();
    ImageMetadata metadata;
    metadata.software = std::string("lhr ") + LHR_VERSION;
    metadata.camera = camera;
    metadata.notes = {{"lhr:method", method},
                      {"lhr:content", "linear radiance, in the units of the scene's emission Ke"}};
    write_image(outputs, out_dir / "image.exr", view.radiance_image, metadata);
    metadata.notes.back().second = "display values, tone-mapped (see stats.json tone_map)";
    write_image(outputs, out_dir / "image.png", view.display_image, metadata);
    // Timings and memory vary from run to run; everything else does not.
    doc["seconds"]["output"] = seconds_since(t_output);
    doc["seconds"]["total"] = seconds_since(t_start);
    doc["peak_memory_mib"] = peak_rss_mib();
    write_json_file(outputs, out_dir / "stats.json", doc);
    throw_if_interrupted();
    outputs.publish();
  } catch (const Interrupted& e) {
    std::cerr << "lhr solve: " << e.what() << "\n";
    return kExitInterrupted;
  }

  if (!quiet) {
    std::cerr << "lhr solve: " << method << ", " << doc["surfaces"] << " surfaces, " << doc["elements"]
              << " elements, " << doc["links"] << " links, " << doc["iterations"] << " iterations, "
              << seconds_since(t_start) << " s -> " << out_dir.string() << "\n";
  }
  return kExitOk;
}

}  // namespace lhr::app
