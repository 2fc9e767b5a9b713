#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include <tbb/global_control.h>

#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/options.hpp"
#include "apps/tone_options.hpp"
#include "io/image_io.hpp"
#include "io/input_error.hpp"
#include "io/mesh_io.hpp"
#include "io/output_dir.hpp"
#include "io/scene_loader.hpp"
#include "render/image_metrics.hpp"
#include "render/path_tracer.hpp"
#include "render/vertex_reference.hpp"

namespace lhr::app {

namespace {

void require_extension(const std::filesystem::path& path, const char* ext, const char* flag) {
  if (path.extension() != ext) throw po::error(std::string(flag) + " must name a " + ext + " file");
}

}  // namespace

int run_reference(const Args& args) {
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")
      ("out,o", po::value<std::string>()->required(), "EXR of the linear radiance (a .ply with --at-vertices)")
      ("at-vertices", po::value<std::string>(),
       "MESH.ply from lhr solve: path-trace the radiance leaving each of its vertices (on its own surface's "
       "side) instead of an image; --out names a .ply with the same vertices and faces, the estimate in "
       "radiance_r/g/b and the standard error of its luminance in radiance_stderr")
      ("png", po::value<std::string>(), "also write the tone-mapped image here")
      ("spp", po::value<int>()->default_value(64),
       "samples per pixel or vertex (the first round's with --target-noise)")
      ("seed", po::value<std::uint64_t>()->default_value(1), "random seed; same seed, same image")
      ("target-noise", double_value(0.0),
       "keep doubling the samples until the relative noise (RMS standard error of the pixel or vertex "
       "means over their mean luminance) is at most this, e.g. 0.01 (0: render --spp samples)")
      ("max-spp", po::value<int>()->default_value(1024),
       "with --target-noise: stop at this many samples per pixel or vertex")
      ("jitter", "spread the samples uniformly over each pixel (an antialiased image) instead of tracing "
       "them all through the pixel centre, the point the Gouraud view of lhr solve samples")
      ("threads", po::value<int>()->default_value(0), "worker threads (0: all cores); results do not depend on it")
      ("quiet,q", "print nothing but errors")
      ("verbose,v", "print progress lines even when stderr is not a terminal");
  add_tone_map_options(visible);
  po::variables_map vm;
  if (!parse_command_line(args,
                          "usage: lhr reference SCENE --out REF.exr [--png REF.png] [--spp N] [options]\n"
                          "       lhr reference SCENE --at-vertices MESH.ply --out REF.ply [--spp N] [options]\n\n"
                          "Renders SCENE from its camera by unbiased Monte Carlo path tracing (next-event\n"
                          "estimation and cosine-weighted bounces combined by multiple importance sampling,\n"
                          "Russian roulette), independently of the radiosity solvers, and reports the\n"
                          "image's noise. Background pixels are 0. With --at-vertices it estimates the\n"
                          "radiance leaving each vertex of a mesh lhr solve exported, for lhr compare\n"
                          "MESH.ply REF.ply; its display colours use the tone flags, defaults from the\n"
                          "vertices' luminance.",
                          visible, Positional{"scene"}, vm)) {
    return kExitOk;
  }
  const bool quiet = vm.count("quiet") > 0;
  const bool verbose = vm.count("verbose") > 0 && !quiet;
  const bool progress = !quiet && (verbose || ::isatty(STDERR_FILENO));
  PathTraceOptions options;
  options.spp = vm["spp"].as<int>();
  options.seed = vm["seed"].as<std::uint64_t>();
  options.target_noise = vm["target-noise"].as<double>();
  options.max_spp = vm["max-spp"].as<int>();
  options.jitter = vm.count("jitter") > 0;
  options.checkpoint = throw_if_interrupted;
  if (options.spp < 2) throw po::error("--spp must be at least 2 (the noise estimate needs two halves)");
  if (!(options.target_noise >= 0) || !std::isfinite(options.target_noise)) {
    throw po::error("--target-noise must be zero or positive");
  }
  if (options.target_noise > 0 && options.max_spp < options.spp) throw po::error("--max-spp must be at least --spp");
  const int threads = vm["threads"].as<int>();
  if (threads < 0) throw po::error("--threads must be 0 or positive");
  const std::filesystem::path out = vm["out"].as<std::string>();
  std::optional<std::filesystem::path> at_vertices;
  if (vm.count("at-vertices")) {
    at_vertices = vm["at-vertices"].as<std::string>();
    if (vm.count("png") || options.jitter) throw po::error("--png and --jitter apply to images, not --at-vertices");
  }
  require_extension(out, at_vertices ? ".ply" : ".exr", "--out");
  std::optional<std::filesystem::path> png;
  if (vm.count("png")) {
    png = vm["png"].as<std::string>();
    require_extension(*png, ".png", "--png");
  }
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism,
                                   threads > 0 ? static_cast<std::size_t>(threads)
                                               : tbb::global_control::active_value(
                                                     tbb::global_control::max_allowed_parallelism));

  install_interrupt_handlers();
  const auto t_start = Clock::now();
  const LoadResult loaded = load_scene(vm["scene"].as<std::string>());
  if (!quiet) {
    for (const std::string& w : loaded.warnings) std::cerr << "lhr reference: warning: " << w << "\n";
  }
  const Scene& scene = loaded.scene;
  const ToneMapSettings tone = tone_settings_from(vm, &scene.settings.tone_map);
  const Camera camera = scene.camera.value_or(framing_camera(scene));
  // Refuse unusable output locations before the work, not after.
  for (const std::filesystem::path& path : {out, png.value_or(out)}) {
    prepare_output_directory(path.has_parent_path() ? path.parent_path() : std::filesystem::path("."));
  }

  const PathTracer tracer(scene);
  if (tracer.emitter_triangle_count() == 0 && !quiet) {
    std::cerr << "lhr reference: warning: the scene has no emitter; the " << (at_vertices ? "mesh" : "image")
              << " is black\n";
  }
  const RawMesh mesh = at_vertices ? read_raw_mesh(*at_vertices) : RawMesh{};
  if (verbose && at_vertices) {
    std::cerr << "lhr reference: " << tracer.triangle_count() << " triangles (" << tracer.emitter_triangle_count()
              << " emitting), tracing " << mesh.points.size() << " vertices of " << at_vertices->string() << "\n";
  } else if (verbose) {
    std::cerr << "lhr reference: " << tracer.triangle_count() << " triangles (" << tracer.emitter_triangle_count()
              << " emitting), rendering " << camera.width << "x" << camera.height << "\n";
  }
  auto last_print = Clock::now() - std::chrono::seconds(1);
  const auto report = [&](const PathTraceProgress& p) {
    if (!progress || seconds_since(last_print) < (verbose ? 1.0 : 0.2)) return;
    last_print = Clock::now();
    std::ostringstream line;
    line << std::fixed << "\rsamples " << p.spp_done << " -> " << p.spp_round_end
         << (at_vertices ? " per vertex: " : " per pixel: ")
         << std::setprecision(0) << 100.0 * p.round_fraction << "%";
    if (p.spp_done > 0) line << std::setprecision(2) << " (noise so far " << 100.0 * p.noise << " %)";
    if (verbose) {
      std::cerr << line.str().substr(1) << "\n";
    } else {
      std::cerr << line.str() << "   " << std::flush;
    }
  };
  if (at_vertices) {
    VertexReference reference;
    try {
      reference = trace_vertex_reference(tracer, mesh, options, report);
    } catch (const Interrupted& e) {
      if (progress && !verbose) std::cerr << "\n";
      std::cerr << "lhr reference: " << e.what() << "\n";
      return kExitInterrupted;
    } catch (const std::invalid_argument& e) {
      throw InputError(*at_vertices, e.what());
    }
    if (progress && !verbose) std::cerr << "\r" << std::string(79, ' ') << "\r";
    write_mesh(out, vertex_reference_export(mesh, reference, tone));
    if (!quiet) {
      std::cerr << "lhr reference: " << reference.spp << " samples per vertex at " << reference.radiance.size()
                << " vertices in " << reference.rounds << (reference.rounds == 1 ? " round" : " rounds")
                << ", noise " << 100.0 * reference.noise << " % (RMS standard error " << reference.noise_rms
                << " of mean luminance " << reference.mean_luminance << "), " << seconds_since(t_start) << " s -> "
                << out.string() << "\n";
      if (options.target_noise > 0 && reference.noise > options.target_noise) {
        std::cerr << "lhr reference: warning: --max-spp reached before the target noise\n";
      }
    }
    return kExitOk;
  }

  ReferenceImage reference;
  try {
    reference = tracer.render(camera, options, report);
  } catch (const Interrupted& e) {
    if (progress && !verbose) std::cerr << "\n";
    std::cerr << "lhr reference: " << e.what() << "\n";
    return kExitInterrupted;
  }
  if (progress && !verbose) std::cerr << "\r" << std::string(79, ' ') << "\r";

  AtomicOutputs outputs;
  ImageMetadata metadata;
  metadata.software = std::string("lhr ") + LHR_VERSION;
  metadata.camera = camera;
  metadata.notes = {{"lhr:method", "path tracing, " + std::to_string(reference.spp) + " samples per pixel"},
                    {"lhr:content", "linear radiance, in the units of the scene's emission Ke"}};
  write_image(outputs, out, reference.radiance, metadata);
  if (png) {
    const auto tone_map = reference_tone_map(tone, reference.radiance, reference.mask);
    Image display(reference.radiance.width, reference.radiance.height);
    for (std::size_t i = 0; i < reference.mask.size(); ++i) {
      const float* p = &reference.radiance.rgb[3 * i];
      const Rgb d = tone_map->display_rgb(Rgb(p[0], p[1], p[2]));
      for (int c = 0; c < 3; ++c) display.rgb[3 * i + c] = static_cast<float>(d[c]);
    }
    metadata.notes.back().second = "display values, tone-mapped";
    write_image(outputs, *png, display, metadata);
  }
  outputs.publish();
  if (!quiet) {
    std::cerr << "lhr reference: " << reference.spp << " samples per pixel in " << reference.rounds
              << (reference.rounds == 1 ? " round" : " rounds") << ", noise " << 100.0 * reference.noise
              << " % (RMS standard error " << reference.noise_rms << " of mean luminance "
              << reference.mean_luminance << "), " << seconds_since(t_start) << " s -> " << out.string() << "\n";
    if (options.target_noise > 0 && reference.noise > options.target_noise) {
      std::cerr << "lhr reference: warning: --max-spp reached before the target noise\n";
    }
  }
  return kExitOk;
}

}  // namespace lhr::app
