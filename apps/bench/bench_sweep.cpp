#include "apps/bench/bench_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "apps/bench/child_process.hpp"
#include "apps/bench/gnuplot_chart.hpp"
#include "io/atomic_file.hpp"
#include "io/image_io.hpp"
#include "io/input_error.hpp"
#include "io/json_file.hpp"
#include "render/image_metrics.hpp"
#include "render/path_tracer.hpp"

namespace lhr {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string one_decimal(double v) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << v;
  return s.str();
}


// "cornell" for cornell.scene.json, "room" for room.obj.
std::string scene_name(const std::filesystem::path& scene) {
  std::string name = scene.filename().string();
  for (const std::string suffix : {".scene.json", ".json", ".obj", ".ply", ".off"}) {
    if (name.size() > suffix.size() && name.ends_with(suffix)) return name.substr(0, name.size() - suffix.size());
  }
  return name;
}

void write_text_atomically(const std::filesystem::path& path, const std::string& text) {
  write_atomically(path, [&](const std::filesystem::path& temp) {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw std::runtime_error(path.string() + ": cannot write");
  });
}

std::string describe_failure(const ChildResult& r) {
  return r.signal != 0 ? "ended by signal " + std::to_string(r.signal) : "exit " + std::to_string(r.exit_code);
}

// Metrics of run images against the reference, as `lhr compare --scene`
// computes them: background where the camera's pixel-centre ray misses, the
// tone map's defaults taken from the reference.
class Scorer {
 public:
  Scorer(const Scene& scene, const Camera& camera, const std::filesystem::path& reference_path,
         const ToneMapSettings& tone)
      : reference_(read_image(reference_path)) {
    if (reference_.width != camera.width || reference_.height != camera.height) {
      throw InputError(reference_path, "is " + std::to_string(reference_.width) + "x" +
                                           std::to_string(reference_.height) + " pixels but the scene's camera is " +
                                           std::to_string(camera.width) + "x" + std::to_string(camera.height));
    }
    mask_ = PathTracer(scene).coverage(camera);
    if (std::count(mask_.begin(), mask_.end(), 1) == 0) {
      throw InputError(scene.source, "the camera sees no surface: there is nothing to compare");
    }
    tone_ = reference_tone_map(tone, reference_, mask_);
  }

  ImageMetrics score(const std::filesystem::path& image_path) const {
    const Image image = read_image(image_path);
    if (image.width != reference_.width || image.height != reference_.height) {
      throw InputError(image_path, "is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                       " pixels but the reference is " + std::to_string(reference_.width) + "x" +
                                       std::to_string(reference_.height));
    }
    return compare_images(image, reference_, mask_, *tone_);
  }

 private:
  Image reference_;
  std::vector<std::uint8_t> mask_;
  std::unique_ptr<ToneMap> tone_;
};

// Makes DIR/reference.exr (and .png) with `lhr reference`; false when stopped.
bool make_reference(const BenchSettings& settings, const std::filesystem::path& exr,
                    const std::function<bool()>& stop_requested, std::ostream* log) {
  const std::filesystem::path dir = settings.out_dir;
  std::vector<std::string> args{"reference", settings.scene.string(), "--seed", std::to_string(kReferenceSeed),
                                "--out", exr.string(), "--png", (dir / "reference.png").string()};
  if (settings.reference_noise > 0) {
    // Rounds double the samples from here until the noise is low enough.
    const int first = std::min(16, settings.reference_max_spp);
    args.insert(args.end(), {"--spp", std::to_string(first), "--target-noise",
                             format_parameter(settings.reference_noise), "--max-spp",
                             std::to_string(settings.reference_max_spp)});
  } else {
    args.insert(args.end(), {"--spp", std::to_string(settings.reference_max_spp)});
  }
  args.insert(args.end(), settings.reference_arguments.begin(), settings.reference_arguments.end());
  // Its messages go straight to our stderr: its progress shows on a terminal.
  if (!log) args.push_back("--quiet");
  if (log) {
    *log << "reference: path tracing " << exr.string() << " ";
    if (settings.reference_noise > 0) {
      *log << "to " << format_parameter(100.0 * settings.reference_noise) << " % noise (at most "
           << settings.reference_max_spp << " samples per pixel)";
    } else {
      *log << "with " << settings.reference_max_spp << " samples per pixel";
    }
    *log << " ..." << std::endl;
  }
  ChildOptions options;
  options.stop_requested = stop_requested;
  const ChildResult r = run_child(settings.executable, args, options);
  // A terminal's Ctrl-C reaches the child too, which may end before we see it.
  if (r.stopped || (r.exit_code != 0 && stop_requested && stop_requested())) return false;
  if (r.exit_code != 0) throw std::runtime_error("the reference failed (lhr reference " + describe_failure(r) + ")");
  if (log) *log << "reference: " << one_decimal(r.seconds) << " s" << std::endl;
  return true;
}

}  // namespace

BenchOutcome run_bench(const Scene& scene, const Camera& camera, const BenchSettings& settings,
                       const std::function<bool()>& stop_requested, std::ostream* log) {
  const auto t_start = Clock::now();
  const std::filesystem::path dir = settings.out_dir;
  std::filesystem::create_directories(dir / "runs");
  BenchOutcome outcome;
  const auto stop = [&] { return stop_requested && stop_requested(); };

  // The reference first: every row is scored against it.
  std::filesystem::path reference = dir / "reference.exr";
  if (settings.reference) {
    reference = *settings.reference;
    if (log) *log << "reference: " << reference.string() << " (given)\n";
  } else if (std::filesystem::exists(reference)) {
    if (log) *log << "reference: " << reference.string() << " (made earlier; delete it for a new one)\n";
  } else if (!make_reference(settings, reference, stop_requested, log)) {
    outcome.interrupted = true;
    return outcome;
  }
  const Scorer scorer(scene, camera, reference, settings.tone);

  const std::size_t n = settings.runs.size();
  const auto prefix = [&](std::size_t i) {
    const BenchRun& run = settings.runs[i];
    std::ostringstream s;
    s << "[" << i + 1 << "/" << n << "] " << bench_method_name(run.method) << " " << run.label();
    return s.str();
  };
  const auto result_text = [](const BenchRow& row) {
    std::ostringstream ratio;
    ratio << std::fixed << std::setprecision(3) << row.metrics.mean_ratio;
    return one_decimal(row.record["seconds_total"].get<double>()) + " s, " + one_decimal(row.metrics.rel_within_10) +
           " % within 10 % (luminance), mean ratio " + ratio.str();
  };
  std::vector<std::optional<BenchRow>> slots(n);
  std::vector<std::vector<std::string>> arguments(n);
  const auto write_csv = [&] {
    std::vector<BenchRow> rows;
    for (const auto& slot : slots) {
      if (slot) rows.push_back(*slot);
    }
    write_text_atomically(dir / "bench.csv", bench_csv(rows));
    return rows;
  };

  // Rows finished by an earlier bench with the same arguments are kept; the
  // metrics are recomputed from the run's image, against the reference in use
  // now, so row.json holds no metric and a row written before a metric
  // existed gets it too.
  for (std::size_t i = 0; i < n; ++i) {
    const BenchRun& run = settings.runs[i];
    arguments[i] = bench_run_arguments(run, settings.scene.string(), settings.solve_arguments,
                                       settings.reference_arguments);
    const std::filesystem::path run_dir = dir / "runs" / run.id();
    if (!std::filesystem::exists(run_dir / "row.json") || !std::filesystem::exists(run_dir / "image.exr")) continue;
    nlohmann::json record;
    try {
      std::ifstream in(run_dir / "row.json");
      record = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception&) {
      continue;  // unreadable: run it again
    }
    if (!record.is_object() || record.value("arguments", nlohmann::json()) != nlohmann::json(arguments[i])) {
      if (log) *log << prefix(i) << ": made with other settings, running it again\n";
      continue;
    }
    slots[i] = BenchRow{run, record, scorer.score(run_dir / "image.exr")};
    ++outcome.reused;
    if (log) *log << prefix(i) << ": done earlier, " << result_text(*slots[i]) << "\n";
  }
  std::vector<BenchRow> rows = write_csv();

  for (std::size_t i = 0; i < n; ++i) {
    if (slots[i]) continue;
    const BenchRun& run = settings.runs[i];
    if (stop()) {
      outcome.interrupted = true;
      return outcome;
    }
    if (settings.max_seconds > 0 && seconds_since(t_start) >= settings.max_seconds) {
      outcome.left.push_back(run);
      continue;
    }
    const std::filesystem::path run_dir = dir / "runs" / run.id();
    std::filesystem::create_directories(run_dir);
    // A stale row must not outlive a run that is stopped half-way.
    std::filesystem::remove(run_dir / "row.json");
    if (log) *log << prefix(i) << " ... " << std::flush;
    std::vector<std::string> args = arguments[i];
    if (run.method == BenchMethod::kPath) {
      args.insert(args.end(), {"--out", (run_dir / "image.exr").string(), "--quiet"});
    } else {
      args.insert(args.end(), {"--out", run_dir.string(), "--quiet"});
    }
    ChildOptions options;
    options.log = run_dir / "log.txt";
    options.stop_requested = stop_requested;
    const ChildResult r = run_child(settings.executable, args, options);
    if (r.stopped || (r.exit_code != 0 && stop())) {
      if (log) *log << "stopped" << std::endl;
      outcome.interrupted = true;
      return outcome;
    }
    if (r.exit_code != 0) {
      if (log) *log << "failed" << std::endl;
      throw std::runtime_error("run " + run.id() + " failed (lhr " + args[0] + " " + describe_failure(r) +
                               "): " + last_log_line(options.log) + " (log: " + options.log.string() + ")");
    }
    nlohmann::json stats;  // the path tracer writes none
    if (run.method != BenchMethod::kPath) {
      std::ifstream in(run_dir / "stats.json");
      try {
        stats = nlohmann::json::parse(in);
      } catch (const nlohmann::json::exception& e) {
        throw InputError(run_dir / "stats.json", std::string("cannot be read: ") + e.what());
      }
    }
    const nlohmann::json record = bench_record(arguments[i], r.seconds, r.peak_rss_bytes, stats);
    slots[i] = BenchRow{run, record, scorer.score(run_dir / "image.exr")};
    // The row last: a run is finished once its row.json exists.
    write_json_file(run_dir / "row.json", record);
    ++outcome.ran;
    rows = write_csv();
    if (log) *log << result_text(*slots[i]) << std::endl;
  }

  // Seconds to reach each target, once the sweep is whole: a method's
  // fastest run to get there may be any of its runs.
  const std::vector<BenchReach> reach = bench_reach(rows, settings.reach_targets);
  write_text_atomically(dir / "reach.csv", reach_csv(rows, reach));
  if (outcome.left.empty()) outcome.reach = reach_summary(rows, reach);

  const std::vector<Chart> charts = bench_charts(scene_name(settings.scene), rows, settings.reach_targets);
  if (!charts.empty()) {
    write_text_atomically(dir / "charts.gp", gnuplot_script("bench.csv", 1, charts));
    if (draw_charts(dir / "charts.gp", charts)) {
      for (const Chart& chart : charts) outcome.charts.push_back(dir / chart.file);
    } else {
      outcome.gnuplot_missing = true;
    }
  }
  return outcome;
}

}  // namespace lhr
