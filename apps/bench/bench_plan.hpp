#pragma once
// What `lhr bench` runs and what it reports (issue 5, docs/design.md §5): the sweep
// of both radiosity methods and the path tracer over their cost parameters,
// the command line of each run, and bench.csv. No process is started here,
// so all of it is testable on its own (the sweep itself: apps/bench/bench_sweep).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/bench/gnuplot_chart.hpp"
#include "render/image_metrics.hpp"

namespace lhr {

enum class BenchMethod { kLinear, kClassical, kPath };

// "linear", "classical", "path": the method column of bench.csv.
const char* bench_method_name(BenchMethod method);

// One run of the sweep: a method and its cost parameter(s).
struct BenchRun {
  BenchMethod method = BenchMethod::kLinear;
  double eps_link = 0.0;   // linear
  double eps_pixel = 0.0;  // linear
  double eps_bf = 0.0;     // classical
  int spp = 0;             // path tracer

  // Directory name under DIR/runs: "linear-10-0.3", "classical-0.003", "path-64".
  std::string id() const;
  // "eps_link=10 eps_pixel=0.3", "eps_bf=0.003", "spp=64" (no comma: a CSV cell).
  std::string label() const;
  bool operator==(const BenchRun&) const = default;
};

// The shortest plain decimal text of a parameter, the same on every run:
// 40, 0.5, 0.003 (never an exponent, at most 10 decimals).
std::string format_parameter(double value);

// Lists as the command line gives them. Each throws std::invalid_argument
// with a one-line message naming the option and the bad item:
// "40/1,20/0.5" (eps_link/eps_pixel pairs, both positive),
// "0.03,0.01" (eps_bf, positive), "4,16" (samples per pixel, integers ≥ 2),
// "linear,classical,path" (any of the three, each at most once).
std::vector<BenchRun> parse_linear_list(const std::string& text);
std::vector<BenchRun> parse_classical_list(const std::string& text);
std::vector<BenchRun> parse_spp_list(const std::string& text);
std::vector<BenchMethod> parse_method_list(const std::string& text);

// The sweep in its fixed order: linear, classical, path; each method's runs
// in the order its list gives (the defaults go from coarse to fine).
std::vector<BenchRun> plan_bench(const std::vector<BenchMethod>& methods, const std::vector<BenchRun>& linear,
                                 const std::vector<BenchRun>& classical, const std::vector<BenchRun>& path);

// The path tracer's runs use another seed than the reference, so that no
// run shares the reference's samples.
constexpr std::uint64_t kReferenceSeed = 1;
constexpr std::uint64_t kPathRunSeed = 2;

// The `lhr` arguments of a run, without its output location: "solve SCENE
// --method M --eps-... ARGS..." or "reference SCENE --spp N --seed S ARGS...",
// with the caller's shared arguments appended (meshing, tone map, threads).
// A finished run records them; one whose recorded arguments differ is not
// reused.
std::vector<std::string> bench_run_arguments(const BenchRun& run, const std::string& scene,
                                             const std::vector<std::string>& solve_arguments,
                                             const std::vector<std::string>& reference_arguments);

// A finished run: what its process measured (row.json) and its image's
// metrics against the reference.
struct BenchRow {
  BenchRun run;
  // {"arguments": [...], "seconds_total": wall-clock s, "peak_rss_bytes": n,
  //  "stats": the run's stats.json, or null for the path tracer}
  nlohmann::json record;
  ImageMetrics metrics;
};

// The record of a run that just finished.
nlohmann::json bench_record(const std::vector<std::string>& arguments, double seconds_total,
                            std::size_t peak_rss_bytes, const nlohmann::json& stats);

// bench.csv's columns, in order (documented in `lhr bench --help` and README).
const std::vector<std::string>& bench_csv_columns();
// The 1-based index of a column (as gnuplot counts); std::logic_error if none.
int bench_csv_column(const std::string& name);

// Header and one line per row, in the order given; fixed decimals; an empty
// cell where a column does not apply to the method (or PSNR is infinite).
std::string bench_csv(const std::vector<BenchRow>& rows);

// The charts of bench.csv (the paper's figs. 9-10 and their cost axes): %
// of pixels within 10 % and 15 % against links, against seconds_total and
// against peak memory, log x, one curve per method that has rows (the path
// tracer has no links). title: the scene's name. No rows, no charts.
// reach_targets: a dashed line at each on the rel_within_10 panels.
std::vector<Chart> bench_charts(const std::string& title, const std::vector<BenchRow>& rows,
                                const std::vector<double>& reach_targets = {});

// Seconds to reach an accuracy (issue 13): for each method of the sweep, the
// fastest of its finished runs whose relative norm (rel_within_10) is at
// least a target, side by side with the other methods of the same sweep. The
// figure is a measured run, not a fitted curve: the wall clock of a run that
// got there, so at most what the method needs at the sweep's settings. A
// method none of whose runs got there reports its best.
struct BenchReach {
  double target = 0.0;  // % of pixels within 10 %
  BenchMethod method = BenchMethod::kLinear;
  std::optional<std::size_t> row;  // index of the fastest run that reached it
  double best = 0.0;               // the method's highest rel_within_10
};

// "90,95": each in (0, 100], none twice; std::invalid_argument naming --reach
// and the bad item.
std::vector<double> parse_reach_list(const std::string& text);

// Per target in the order given, one entry per method that has rows (linear,
// classical, path). A run's time is its seconds_total.
std::vector<BenchReach> bench_reach(const std::vector<BenchRow>& rows, const std::vector<double>& targets);

// reach.csv: target, method, reached (1/0), seconds_total, parameters,
// rel_within_10, links, peak_rss_bytes, path_over_this (the path tracer's
// seconds to the same target over this method's, where both got there);
// fixed decimals, an empty cell where nothing applies.
std::string reach_csv(const std::vector<BenchRow>& rows, const std::vector<BenchReach>& reach);

// One line per target for the terminal: "95 % within 10 %: linear 12.3 s
// (eps_link=10 eps_pixel=0.3), classical not reached (best 93.1 %), path
// 40.2 s (spp=256); linear 3.3x sooner than the path tracer" (or "slower").
std::vector<std::string> reach_summary(const std::vector<BenchRow>& rows, const std::vector<BenchReach>& reach);

}  // namespace lhr
