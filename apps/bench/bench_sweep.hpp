#pragma once
// `lhr bench` itself (issue 5): the reference, then every run of the plan
// in a child process of its own (the `lhr` executable), measured for wall
// time and peak memory and scored against the reference; bench.csv after
// each run; charts at the end. A run whose row.json records the same
// arguments is not run again, so a stopped sweep resumes where it stopped.
//
// DIR/reference.exr (.png)          path-traced reference, reused if present
// DIR/runs/ID/                      one run: its outputs, log.txt, row.json
// DIR/bench.csv, charts.gp, *.png   the table and its charts
// DIR/reach.csv                     seconds each method took to reach each target

#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "apps/bench/bench_plan.hpp"
#include "mesh/scene.hpp"
#include "render/solution_view.hpp"

namespace lhr {

struct BenchSettings {
  std::filesystem::path scene;       // as the runs are given it
  std::filesystem::path out_dir;     // DIR
  std::filesystem::path executable;  // the `lhr` the runs execute
  std::vector<BenchRun> runs;        // plan_bench's order
  std::vector<std::string> solve_arguments;      // appended to every `lhr solve`
  std::vector<std::string> reference_arguments;  // appended to every `lhr reference`
  std::optional<std::filesystem::path> reference;  // an EXR to use instead of DIR/reference.exr
  double reference_noise = 0.01;  // target relative noise of the reference (0: reference_max_spp samples)
  int reference_max_spp = 4096;
  double max_seconds = 0.0;  // start no run after this long (0: no limit)
  ToneMapSettings tone;        // the metrics' tone map, as `lhr compare --scene` takes it
  std::vector<double> reach_targets{90.0, 95.0};  // % within 10 %: seconds to reach each (reach.csv)
};

struct BenchOutcome {
  std::size_t ran = 0;
  std::size_t reused = 0;
  std::vector<BenchRun> left;  // not started because of max_seconds
  bool interrupted = false;    // stop_requested ended it; finished rows are kept
  bool gnuplot_missing = false;
  std::vector<std::filesystem::path> charts;  // drawn
  std::vector<std::string> reach;             // reach_summary's lines, once every run has finished
};

// scene and camera: what settings.scene loads to (for the coverage mask and
// the image size). log: progress, one line per run (nullptr: silent).
// Throws std::runtime_error (InputError for bad input) naming the file or
// the run that failed, with the first problem's message.
BenchOutcome run_bench(const Scene& scene, const Camera& camera, const BenchSettings& settings,
                       const std::function<bool()>& stop_requested, std::ostream* log);

}  // namespace lhr
