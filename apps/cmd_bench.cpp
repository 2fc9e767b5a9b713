#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>
#include <string>

#include "apps/bench/bench_plan.hpp"
#include "apps/bench/bench_sweep.hpp"
#include "apps/commands.hpp"
#include "apps/interrupt.hpp"
#include "apps/options.hpp"
#include "io/output_dir.hpp"
#include "apps/tone_options.hpp"
#include "io/scene_loader.hpp"

namespace lhr::app {

namespace {

constexpr const char* kUsage =
    "usage: lhr bench SCENE --out DIR [--methods linear,classical,path] [--linear L/P,...]\n"
    "                 [--classical E,...] [--spp N,...] [--max-seconds S] [options]\n"
    "\n"
    "Charts image accuracy against cost for both radiosity methods and the path tracer\n"
    "(the paper's figs. 9-10, against links, time and memory). The primary figure is the\n"
    "relative norm on linear luminance (% of pixels within 10 % and 15 % of the\n"
    "reference's luminance, and the mean ratio); the paper's display-value norm is kept\n"
    "as a secondary figure: it saturates near 100 % on dim tone-mapped images.\n"
    "\n"
    "1. Reference: DIR/reference.exr (and .png), path-traced by 'lhr reference' with seed 1\n"
    "   until its relative noise is at most --reference-noise or it has\n"
    "   --reference-max-spp samples per pixel (its progress shows on a terminal).\n"
    "   An existing DIR/reference.exr is reused; --reference FILE uses FILE instead.\n"
    "2. Runs, in this order: 'lhr solve --method linear' for each eps_link/eps_pixel pair\n"
    "   of --linear, 'lhr solve --method classical' for each eps_bf of --classical, and\n"
    "   'lhr reference' (seed 2, not the reference's samples) for each --spp. Meshing,\n"
    "   camera and tone map are lhr solve's defaults or the scene file's; the meshing,\n"
    "   solver, tone-map and --threads flags below are passed on to every run.\n"
    "3. Each run is a child process of its own (this lhr executable), writing into\n"
    "   DIR/runs/ID/ (ID e.g. linear-10-0.3, classical-0.003, path-64; log.txt has its\n"
    "   messages); its peak memory is the child's maximum resident set (wait4), its\n"
    "   time the child's wall clock. Its image.exr is then compared with the reference\n"
    "   as 'lhr compare IMAGE REF --scene SCENE' does. The metrics are not stored: a\n"
    "   finished run is scored again from its image.exr whenever bench.csv is written.\n"
    "4. A run is finished when DIR/runs/ID/row.json exists; a finished run made with\n"
    "   the same arguments is not run again, so the same command resumes a stopped\n"
    "   sweep. bench.csv is rewritten from all finished rows after every run.\n"
    "   --max-seconds S starts no run after S seconds and lists what was left.\n"
    "   Ctrl-C or SIGTERM stops the running child and exits with code 130, keeping\n"
    "   the finished rows.\n"
    "5. Charts: DIR/charts.gp, run by gnuplot (pngcairo, else png) into\n"
    "   accuracy_vs_links.png, accuracy_vs_seconds.png and accuracy_vs_memory.png,\n"
    "   each against links, seconds_total and peak_rss_bytes, log x, one curve per\n"
    "   method (the path tracer has no links). Top row, primary: rel_within_10,\n"
    "   rel_within_15 and mean_ratio (a dashed line at 1); bottom row, secondary: the\n"
    "   paper's within_10 and within_15 and the display rmse.\n"
    "   Without gnuplot: bench.csv and charts.gp, and one warning.\n"
    "6. Seconds to reach: for each --reach target T and each method, the fastest\n"
    "   finished run with rel_within_10 >= T (a measured run, not a fitted curve),\n"
    "   printed side by side once the sweep is whole and written to DIR/reach.csv\n"
    "   (target, method, reached, seconds_total, parameters, rel_within_10, links,\n"
    "   peak_rss_bytes, path_over_this: the path tracer's seconds over this\n"
    "   method's); a method that never got there shows its best rel_within_10. The\n"
    "   targets are dashed lines on the rel_within_10 panels.\n"
    "\n"
    "bench.csv: one row per finished run, in the order above; fixed decimals; an empty\n"
    "cell where a column does not apply to the method.\n"
    "  method             linear, classical or path\n"
    "  parameters         the run's parameters as one label, e.g. eps_link=10 eps_pixel=0.3\n"
    "  eps_link           linear: the shooter oracle's threshold (--eps-link)\n"
    "  eps_pixel          linear: the receiver oracle's threshold (--eps-pixel)\n"
    "  eps_bf             classical: the BF refinement threshold (--eps-bf)\n"
    "  spp                path: samples per pixel\n"
    "  links              radiosity: links at the end of the solve\n"
    "  nodes              radiosity: quadtree nodes\n"
    "  elements           radiosity: leaf elements\n"
    "  seconds_total      wall clock of the run's process: load, mesh, solve or trace, write\n"
    "  seconds_meshing, seconds_solve, seconds_linking, seconds_refine,\n"
    "  seconds_coefficients, seconds_gather, seconds_push_pull, seconds_oracles,\n"
    "  seconds_importance, seconds_view, seconds_output\n"
    "                     radiosity: phases from the run's stats.json (each method has some)\n"
    "  peak_rss_bytes     the run process's peak resident memory (wait4's ru_maxrss),\n"
    "                     its shared libraries' pages included (over 100 MiB for any lhr\n"
    "                     process); Linux counts a spawned child from its parent's peak,\n"
    "                     lhr bench's own, which is about that of an lhr process at start\n"
    "  graph_bytes        linear: bytes of the interaction graphs' own tables\n"
    "  graph_overhead     linear: graph_bytes over the bytes of geometry, hierarchy,\n"
    "                     vertex values and links (the paper's ~30 %)\n"
    "  data_bytes_per_link\n"
    "                     radiosity: the solver's data (stats.json bytes.total:\n"
    "                     geometry, hierarchy, values, graphs, links) over its links\n"
    "  peak_rss_per_link  radiosity: peak_rss_bytes over links (the process's base,\n"
    "                     over 100 MiB, included: compare it between runs of one scene)\n"
    "  rel_within_10      primary: % of non-background pixels whose linear luminance Y\n"
    "                     is within 10 % of the reference's: |Y - Y_ref| <=\n"
    "                     0.10 max(Y_ref, 1 % of the mean Y_ref) (as lhr compare)\n"
    "  rel_within_15      primary: % within 15 %, likewise\n"
    "  mean_ratio         primary: mean Y / mean Y_ref over those pixels (1: no bias)\n"
    "  within_10          the paper's norm: % of non-background pixels whose display\n"
    "                     value is within 10 % of the display range\n"
    "  within_15          the paper's norm: % within 15 %\n"
    "  rmse               RMS difference of the display values in [0,1]\n"
    "  psnr_db            20 log10(1/rmse)\n"
    "  relative_error     sum |a-b| / sum |b| of the linear radiance";

// Flags given on the command line, passed on to the runs.
const std::set<std::string> kSolveFlags{
    "max-edge",   "min-angle",   "crease-angle", "min-edge",   "max-iterations", "tolerance",  "max-links",
    "max-memory", "visibility-samples", "vis-threshold", "link-power", "eps-vertex", "eps-power", "threads",
    "tone-map",   "adaptation",  "units-to-cd",  "white",      "display-max",    "max-contrast", "gamma"};
const std::set<std::string> kReferenceFlags{"threads",     "tone-map",    "adaptation",   "units-to-cd",
                                            "white",       "display-max", "max-contrast", "gamma"};

std::vector<std::string> tokens_of(const po::parsed_options& parsed, const std::set<std::string>& flags) {
  std::vector<std::string> tokens;
  for (const po::option& o : parsed.options) {
    if (!flags.count(o.string_key)) continue;
    // One spelling for "--flag=v" and "--flag v": a run's recorded arguments
    // decide whether it is reused.
    tokens.push_back("--" + o.string_key);
    tokens.insert(tokens.end(), o.value.begin(), o.value.end());
  }
  return tokens;
}

template <typename T>
std::vector<T> parsed_list(std::vector<T> (*parse)(const std::string&), const std::string& text) {
  try {
    return parse(text);
  } catch (const std::invalid_argument& e) {
    throw po::error(e.what());
  }
}

std::string join_labels(const std::vector<BenchRun>& runs) {
  std::string s;
  for (const BenchRun& run : runs) {
    s += (s.empty() ? "" : ", ") + std::string(bench_method_name(run.method)) + " " + run.label();
  }
  return s;
}

}  // namespace

int run_bench(const Args& args) {
  po::options_description visible("options");
  visible.add_options()("help,h", "show this help")
      ("out,o", po::value<std::string>()->required(), "output directory (created if missing)")
      ("methods", po::value<std::string>()->default_value("linear,classical,path"),
       "which methods to run: any of linear, classical, path")
      ("linear", po::value<std::string>()->default_value("160/4,80/2,40/1,20/0.5,10/0.3,5/0.2"),
       "linear runs: eps_link/eps_pixel pairs, coarse to fine (lhr solve's default is 10/0.3)")
      ("classical", po::value<std::string>()->default_value("0.03,0.01,0.003,0.001"),
       "classical runs: eps_bf values, coarse to fine (lhr solve's default is 0.001)")
      ("spp", po::value<std::string>()->default_value("4,16,64,256"), "path tracer runs: samples per pixel")
      ("reference", po::value<std::string>(), "use this EXR (linear radiance, the scene camera's size) as the "
       "reference instead of DIR/reference.exr")
      ("reference-noise", double_value(0.01),
       "target relative noise of the reference (0: exactly --reference-max-spp samples per pixel)")
      ("reference-max-spp", po::value<int>()->default_value(4096), "samples per pixel at most for the reference")
      ("max-seconds", double_value(0.0), "start no run after this many seconds (0: no limit)")
      ("reach", po::value<std::string>()->default_value("90,95"),
       "accuracy targets, % of pixels within 10 % (relative): the seconds each method took to reach each")
      ("min-edge", po::value<double>(), "lhr solve: smallest element edge (default h/32, finer toward small and on thin surfaces)")
      ("max-iterations", po::value<int>(), "lhr solve: iteration limit")
      ("tolerance", po::value<double>(), "lhr solve: convergence tolerance")
      ("max-links", po::value<std::size_t>(), "lhr solve: stop refining at this many links")
      ("max-memory", po::value<std::string>(), "lhr solve: stop refining before the radiosity data passes this size")
      ("visibility-samples", po::value<int>(), "lhr solve: k, k^2 shadow rays per link")
      ("vis-threshold", po::value<double>(), "lhr solve, linear: visibility difference threshold")
      ("link-power", po::value<double>(), "lhr solve, linear: power fraction at which a surface starts shooting")
      ("eps-vertex", po::value<double>(), "lhr solve, linear: a node's shooter error, relative to its radiance")
      ("eps-power", po::value<double>(), "lhr solve, linear: power an edge's interpolant may misplace")
      ("threads", po::value<int>(), "worker threads of every run (default: all cores)")
      ("quiet,q", "print nothing but errors and warnings");
  add_scene_meshing_options(visible);
  add_tone_map_options(visible);
  po::options_description all;
  all.add(visible);
  all.add_options()("scene", po::value<std::string>()->required(), "scene");
  po::positional_options_description positional;
  positional.add("scene", 1);
  const po::parsed_options parsed = po::command_line_parser(args).options(all).positional(positional).run();
  po::variables_map vm;
  po::store(parsed, vm);
  if (vm.count("help")) {
    std::cout << kUsage << "\n\n" << visible << "\n";
    return kExitOk;
  }
  po::notify(vm);
  const bool quiet = vm.count("quiet") > 0;

  const auto methods = parsed_list(parse_method_list, vm["methods"].as<std::string>());
  const auto linear = parsed_list(parse_linear_list, vm["linear"].as<std::string>());
  const auto classical = parsed_list(parse_classical_list, vm["classical"].as<std::string>());
  const auto path = parsed_list(parse_spp_list, vm["spp"].as<std::string>());
  const auto reach_targets = parsed_list(parse_reach_list, vm["reach"].as<std::string>());
  BenchSettings settings;
  settings.runs = plan_bench(methods, linear, classical, path);
  settings.reach_targets = reach_targets;
  settings.reference_noise = vm["reference-noise"].as<double>();
  settings.reference_max_spp = vm["reference-max-spp"].as<int>();
  settings.max_seconds = vm["max-seconds"].as<double>();
  if (!(settings.reference_noise >= 0) || !std::isfinite(settings.reference_noise)) {
    throw po::error("--reference-noise must be zero or positive");
  }
  if (settings.reference_max_spp < 2) throw po::error("--reference-max-spp must be at least 2");
  if (!(settings.max_seconds >= 0)) throw po::error("--max-seconds must be zero or positive");
  // What lhr solve would refuse, refused before the reference takes its time.
  const auto refuse_unless = [&](const char* flag, auto is_good, const char* what) {
    if (vm.count(flag) && !is_good(vm[flag])) throw po::error("--" + std::string(flag) + " must be " + what);
  };
  using Value = const po::variable_value&;
  refuse_unless("min-edge", [](Value v) { return v.as<double>() >= 0; }, "zero or positive");
  refuse_unless("max-iterations", [](Value v) { return v.as<int>() >= 1; }, "at least 1");
  refuse_unless("tolerance", [](Value v) { return v.as<double>() > 0; }, "positive");
  refuse_unless("visibility-samples", [](Value v) { return v.as<int>() >= 1; }, "at least 1");
  refuse_unless("vis-threshold", [](Value v) { return v.as<double>() > 0; }, "positive");
  refuse_unless("link-power", [](Value v) { return v.as<double>() >= 0; }, "zero or positive");
  refuse_unless("eps-vertex", [](Value v) { return v.as<double>() >= 0; }, "0 (off) or positive");
  refuse_unless("eps-power", [](Value v) { return v.as<double>() > 0; }, "positive");
  refuse_unless("threads", [](Value v) { return v.as<int>() >= 0; }, "0 or positive");
  if (vm.count("reference")) {
    settings.reference = vm["reference"].as<std::string>();
    if (settings.reference->extension() != ".exr") throw po::error("--reference must name a .exr file");
  }

  const auto t_start = Clock::now();
  install_interrupt_handlers();
  const std::filesystem::path scene_path = vm["scene"].as<std::string>();
  const LoadResult loaded = load_scene(scene_path, load_options_from(vm));
  if (!quiet) {
    for (const std::string& w : loaded.warnings) std::cerr << "lhr bench: warning: " << w << "\n";
  }
  const Scene& scene = loaded.scene;
  const Camera camera = scene.camera.value_or(framing_camera(scene));
  meshing_options_from(vm, scene);  // refuses bad meshing flags now, not in every run
  settings.tone = tone_settings_from(vm, &scene.settings.tone_map);
  // Runs see the scene by an absolute path: a resumed sweep matches its
  // recorded arguments from any working directory.
  settings.scene = std::filesystem::absolute(scene_path).lexically_normal();
  settings.out_dir = vm["out"].as<std::string>();
  prepare_output_directory(settings.out_dir);
  std::error_code ec;
  settings.executable = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) settings.executable = "/proc/self/exe";
  settings.solve_arguments = tokens_of(parsed, kSolveFlags);
  settings.reference_arguments = tokens_of(parsed, kReferenceFlags);

  const BenchOutcome outcome = lhr::run_bench(scene, camera, settings, [] { return g_interrupt_signal != 0; },
                                              quiet ? nullptr : &std::cerr);
  const std::size_t finished = outcome.ran + outcome.reused;
  if (outcome.interrupted) {
    std::cerr << "lhr bench: interrupted; " << finished << (finished == 1 ? " finished run is" : " finished runs are")
              << " kept in " << (settings.out_dir / "bench.csv").string() << "\n";
    return kExitInterrupted;
  }
  if (!outcome.left.empty()) {
    std::cerr << "lhr bench: --max-seconds reached; not run (" << outcome.left.size()
              << "): " << join_labels(outcome.left) << "; the same command continues the sweep\n";
  }
  if (outcome.gnuplot_missing) {
    std::cerr << "lhr bench: warning: gnuplot is not on PATH: wrote bench.csv and charts.gp but no chart "
                 "(Debian package gnuplot-nox)\n";
  }
  if (!quiet) {
    std::ostringstream line;
    line << "lhr bench: " << finished << " of " << settings.runs.size() << " runs (" << outcome.reused
         << " done earlier), " << seconds_since(t_start) << " s -> "
         << (settings.out_dir / "bench.csv").string();
    for (const auto& chart : outcome.charts) line << ", " << chart.filename().string();
    std::cerr << line.str() << "\n";
    for (const std::string& reached : outcome.reach) std::cerr << "lhr bench: " << reached << "\n";
  }
  return kExitOk;
}

}  // namespace lhr::app
