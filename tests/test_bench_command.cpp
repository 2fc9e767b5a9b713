// `lhr bench`: its lists, bench.csv's format and charts (no process), and
// one small sweep end to end: the documented columns, one row per run with
// metrics in [0,100], PNG charts, a second run that resumes, and a resumed
// run scored again from its image.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/bench/bench_plan.hpp"
#include "io/image_io.hpp"
#include "test_support.hpp"

namespace lhr {
namespace {

// bench.csv's header as README and `lhr bench --help` document it.
const char* const kDocumentedHeader =
    "method,parameters,eps_link,eps_pixel,eps_bf,spp,links,nodes,elements,seconds_total,seconds_meshing,"
    "seconds_solve,seconds_linking,seconds_refine,seconds_coefficients,seconds_gather,seconds_push_pull,"
    "seconds_oracles,seconds_importance,seconds_view,seconds_output,peak_rss_bytes,graph_bytes,graph_overhead,"
    "data_bytes_per_link,peak_rss_per_link,rel_within_10,rel_within_15,mean_ratio,within_10,within_15,rmse,psnr_db,relative_error";

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.push_back("");
  return parts;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(BenchPlan, ParsesTheListsOfEachMethod) {
  const auto linear = parse_linear_list("40/1, 20/0.5,10/0.3");
  ASSERT_EQ(linear.size(), 3u);
  EXPECT_EQ(linear[1].eps_link, 20.0);
  EXPECT_EQ(linear[1].eps_pixel, 0.5);
  EXPECT_EQ(linear[1].id(), "linear-20-0.5");
  EXPECT_EQ(linear[1].label(), "eps_link=20 eps_pixel=0.5");
  const auto classical = parse_classical_list("0.03,1e-3");
  ASSERT_EQ(classical.size(), 2u);
  EXPECT_EQ(classical[1].id(), "classical-0.001");
  EXPECT_EQ(classical[1].label(), "eps_bf=0.001");
  const auto path = parse_spp_list("4,256");
  ASSERT_EQ(path.size(), 2u);
  EXPECT_EQ(path[1].spp, 256);
  EXPECT_EQ(path[1].id(), "path-256");
  EXPECT_EQ(format_parameter(40), "40");
  EXPECT_EQ(format_parameter(0.0001), "0.0001");
  EXPECT_EQ(format_parameter(2.5), "2.5");

  // Fixed method order whatever order --methods names them in.
  const auto plan = plan_bench(parse_method_list("path,linear"), linear, classical, path);
  ASSERT_EQ(plan.size(), 5u);
  EXPECT_EQ(plan.front().method, BenchMethod::kLinear);
  EXPECT_EQ(plan.back().method, BenchMethod::kPath);

  const auto solve = bench_run_arguments(linear[2], "/s/room.scene.json", {"--max-edge", "140"}, {"--threads", "1"});
  EXPECT_EQ(solve, (std::vector<std::string>{"solve", "/s/room.scene.json", "--method", "linear", "--eps-link", "10",
                                             "--eps-pixel", "0.3", "--max-edge", "140"}));
  const auto trace = bench_run_arguments(path[0], "/s/room.scene.json", {"--max-edge", "140"}, {"--threads", "1"});
  EXPECT_EQ(trace, (std::vector<std::string>{"reference", "/s/room.scene.json", "--spp", "4", "--seed", "2",
                                             "--threads", "1"}));
}

TEST(BenchPlan, BadListsSayWhichOptionAndItem) {
  const auto linear = [](const std::string& t) { return error_of([&] { parse_linear_list(t); }); };
  const auto classical = [](const std::string& t) { return error_of([&] { parse_classical_list(t); }); };
  const auto spp = [](const std::string& t) { return error_of([&] { parse_spp_list(t); }); };
  const auto methods = [](const std::string& t) { return error_of([&] { parse_method_list(t); }); };
  EXPECT_EQ(linear("40-1"), "--linear: \"40-1\" is not eps_link/eps_pixel with two positive numbers (e.g. 10/0.3)");
  EXPECT_NE(linear("10/0").find("\"10/0\""), std::string::npos);
  EXPECT_NE(linear("10/0.3/2").find("\"10/0.3/2\""), std::string::npos);
  EXPECT_EQ(linear("10/0.3,,5/0.2"), "--linear: empty item in \"10/0.3,,5/0.2\"");
  EXPECT_EQ(linear(""), "--linear: empty item in \"\"");
  EXPECT_EQ(linear("10/0.3,10/0.30"), "--linear lists eps_link=10 eps_pixel=0.3 twice");
  EXPECT_EQ(classical("0.01,abc"), "--classical: \"abc\" is not a positive eps_bf (e.g. 0.003)");
  EXPECT_NE(classical("-0.01").find("\"-0.01\""), std::string::npos);
  EXPECT_NE(classical("inf").find("\"inf\""), std::string::npos);
  EXPECT_EQ(spp("4,1.5"), "--spp: \"1.5\" is not a whole number of samples per pixel of at least 2");
  EXPECT_NE(spp("1").find("\"1\""), std::string::npos);
  EXPECT_EQ(methods("linear,radiosity"), "--methods: \"radiosity\" is not linear, classical or path");
  EXPECT_EQ(methods("path,path"), "--methods lists path twice");
}

TEST(BenchPlan, CsvHasFixedDecimalsAndEmptyCellsWhereAColumnDoesNotApply) {
  EXPECT_EQ(split(kDocumentedHeader, ','), bench_csv_columns());
  BenchRow linear{parse_linear_list("10/0.3")[0], {}, {}};
  linear.record = bench_record({"solve"}, 8.43219, 334000128,
                               {{"links", 2506952},
                                {"nodes", 50000},
                                {"elements", 37347},
                                {"seconds", {{"meshing", 0.5}, {"solve", 7.25}, {"oracles", 1.0 / 3.0}}},
                                {"bytes", {{"graphs", 123456}, {"graph_overhead", 0.0912345}, {"total", 250695200}}}});
  linear.metrics.rel_within_10 = 71.5;
  linear.metrics.rel_within_15 = 88.0004;
  linear.metrics.mean_ratio = 0.98765432;
  linear.metrics.within_10 = 94.123456;
  linear.metrics.within_15 = 100.0;
  linear.metrics.rmse = 0.0123456789;
  linear.metrics.psnr_db = 38.17;
  linear.metrics.relative_error = 0.05;
  BenchRow path{parse_spp_list("16")[0], bench_record({"reference"}, 2.0, 50 << 20, nullptr), {}};
  path.metrics.within_10 = 50.0;
  path.metrics.psnr_db = std::numeric_limits<double>::infinity();
  path.metrics.mean_ratio = std::numeric_limits<double>::infinity();
  const std::string csv = bench_csv({linear, path});
  const auto lines = split(csv, '\n');
  ASSERT_EQ(lines.size(), 4u) << csv;  // header, two rows, and the end of the last line
  EXPECT_EQ(lines[0], kDocumentedHeader);
  EXPECT_EQ(lines[1],
            "linear,eps_link=10 eps_pixel=0.3,10,0.3,,,2506952,50000,37347,8.432,0.500,7.250,,,,,,0.333,,,,"
            "334000128,123456,0.0912,100.0,133.2,71.500,88.000,0.987654,94.123,100.000,0.012346,38.170,0.050000");
  EXPECT_EQ(lines[2],
            "path,spp=16,,,,16,,,,2.000,,,,,,,,,,,,52428800,,,,,0.000,0.000,,50.000,0.000,0.000000,,0.000000");
  EXPECT_EQ(lines[3], "");
  for (const std::string& line : {lines[1], lines[2]}) {
    EXPECT_EQ(split(line, ',').size(), bench_csv_columns().size()) << line;
  }
}

TEST(BenchPlan, ChartsLeaveThePathTracerOffTheLinksChart) {
  EXPECT_TRUE(bench_charts("room", {}).empty());
  BenchRow path{parse_spp_list("16")[0], bench_record({"reference"}, 2.0, 1 << 20, nullptr), {}};
  auto charts = bench_charts("room", {path});
  ASSERT_EQ(charts.size(), 2u);
  EXPECT_EQ(charts[0].file, "accuracy_vs_seconds.png");
  EXPECT_EQ(charts[1].file, "accuracy_vs_memory.png");
  BenchRow linear{parse_linear_list("10/0.3")[0], bench_record({"solve"}, 1.0, 1 << 20, {{"links", 10}}), {}};
  charts = bench_charts("room", {linear, path});
  ASSERT_EQ(charts.size(), 3u);
  EXPECT_EQ(charts[0].file, "accuracy_vs_links.png");
  ASSERT_EQ(charts[0].series.size(), 1u);
  EXPECT_EQ(charts[0].series[0].key, "linear");
  EXPECT_EQ(charts[0].x_column, bench_csv_column("links"));
  EXPECT_EQ(charts[1].series.size(), 2u);
  EXPECT_EQ(charts[0].title, "room: image accuracy against links");
  // Top row the primary figures (relative luminance norm, mean ratio with its
  // ideal 1 drawn); bottom row the paper's display norm and the display RMSE.
  ASSERT_EQ(charts[0].panels.size(), 6u);
  EXPECT_EQ(charts[0].panels_per_row, 3);
  const char* const order[] = {"rel_within_10", "rel_within_15", "mean_ratio", "within_10", "within_15", "rmse"};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(charts[0].panels[i].y_column, bench_csv_column(order[i])) << order[i];
    EXPECT_EQ(charts[0].panels[i].y_lines.size(), i == 2 ? 1u : 0u) << order[i];
  }
  const std::string script = gnuplot_script("bench.csv", 1, charts);
  for (const char* part : {"pngcairo", "accuracy_vs_links.png", "accuracy_vs_memory.png", "set logscale x",
                           "strcol(1) eq 'linear'", "title 'path tracer'", "multiplot layout 2,3",
                           "size 1500,960", "set arrow 1 from graph 0, first 1 to graph 1, first 1"}) {
    EXPECT_NE(script.find(part), std::string::npos) << part;
  }
}

// Seconds to reach a target: per method the fastest finished run at or above
// it, whatever order the rows come in; a method that never got there shows
// its best; the path tracer's time over each method's where both got there.
TEST(BenchPlan, SecondsToReachAreTheFastestRunThatGotThere) {
  const auto row = [](const BenchRun& run, double seconds, double within, long links) {
    BenchRow r{run, bench_record({"x"}, seconds, 1 << 20, links > 0 ? nlohmann::json{{"links", links}} : nullptr),
               {}};
    r.metrics.rel_within_10 = within;
    return r;
  };
  const auto linear = parse_linear_list("10/0.3,40/1,160/4");
  const std::vector<BenchRow> rows{row(linear[0], 30.0, 96.0, 3000),
                                   row(linear[1], 10.0, 91.0, 1000),
                                   row(linear[2], 5.0, 80.0, 100),
                                   row(parse_classical_list("0.001")[0], 20.0, 93.0, 5000),
                                   row(parse_spp_list("256")[0], 40.0, 97.0, 0),
                                   row(parse_spp_list("16")[0], 8.0, 85.0, 0)};
  const auto reach = bench_reach(rows, parse_reach_list("90, 95"));
  ASSERT_EQ(reach.size(), 6u);
  const std::optional<std::size_t> expected[] = {1, 3, 4, 0, std::nullopt, 4};
  const BenchMethod order[] = {BenchMethod::kLinear, BenchMethod::kClassical, BenchMethod::kPath};
  for (std::size_t i = 0; i < reach.size(); ++i) {
    EXPECT_EQ(reach[i].target, i < 3 ? 90.0 : 95.0) << i;
    EXPECT_EQ(reach[i].method, order[i % 3]) << i;
    EXPECT_EQ(reach[i].row, expected[i]) << i;
  }
  EXPECT_DOUBLE_EQ(reach[4].best, 93.0);

  const auto lines = reach_summary(rows, reach);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0],
            "90 % within 10 %: linear 10.0 s (eps_link=40 eps_pixel=1), classical 20.0 s (eps_bf=0.001), "
            "path 40.0 s (spp=256); linear 4.0x sooner than the path tracer; classical 2.0x sooner than the "
            "path tracer");
  EXPECT_EQ(lines[1],
            "95 % within 10 %: linear 30.0 s (eps_link=10 eps_pixel=0.3), classical not reached (best 93.0 %), "
            "path 40.0 s (spp=256); linear 1.3x sooner than the path tracer");

  const auto csv = split(reach_csv(rows, reach), '\n');
  ASSERT_EQ(csv.size(), 8u);  // header, six entries, the end of the last line
  EXPECT_EQ(csv[0], "target,method,reached,seconds_total,parameters,rel_within_10,links,peak_rss_bytes,path_over_this");
  EXPECT_EQ(csv[1], "90,linear,1,10.000,eps_link=40 eps_pixel=1,91.000,1000,1048576,4.000");
  EXPECT_EQ(csv[3], "90,path,1,40.000,spp=256,97.000,,1048576,1.000");
  EXPECT_EQ(csv[5], "95,classical,0,,,93.000,,,");

  // Methods without rows are left out; no target reached by anyone.
  const auto only_path = bench_reach({rows[5]}, {99.0});
  ASSERT_EQ(only_path.size(), 1u);
  EXPECT_FALSE(only_path[0].row);
  EXPECT_EQ(reach_summary({rows[5]}, only_path)[0], "99 % within 10 %: path not reached (best 85.0 %)");
  const std::vector<BenchRow> slow{row(linear[0], 60.0, 96.0, 3000), rows[4]};
  EXPECT_EQ(reach_summary(slow, bench_reach(slow, {95.0}))[0],
            "95 % within 10 %: linear 60.0 s (eps_link=10 eps_pixel=0.3), path 40.0 s (spp=256); "
            "linear 1.5x slower than the path tracer");

  EXPECT_EQ(error_of([] { parse_reach_list("0"); }), "--reach: \"0\" is not a percentage in (0, 100]");
  EXPECT_EQ(error_of([] { parse_reach_list("100.5"); }), "--reach: \"100.5\" is not a percentage in (0, 100]");
  EXPECT_EQ(error_of([] { parse_reach_list("95,x"); }), "--reach: \"x\" is not a percentage in (0, 100]");
  EXPECT_EQ(error_of([] { parse_reach_list("95,95"); }), "--reach lists 95 twice");
  EXPECT_EQ(parse_reach_list("100"), std::vector<double>{100.0});
}

// The end-to-end sweep: a coarse Cornell box seen by a 48x36 camera.
class BenchCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(test::fresh_dir("bench_command"));
    const std::string obj = (test::source_dir() / "data/cornell/cornell.obj").string();
    test::write_text(*dir_ / "tiny.scene.json",
                     "{\"mesh\": \"" + obj + "\", \"camera\": {\"eye\": [278, 273, -800], \"target\": [278, 273, 0], "
                     "\"up\": [0, 1, 0], \"fov_y_deg\": 39.3, \"width\": 48, \"height\": 36}}");
  }
  static void TearDownTestSuite() { delete dir_; }

  static std::vector<std::string> bench_args(const std::string& spp = "4,16", std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"bench", (*dir_ / "tiny.scene.json").string(), "--out", (*dir_ / "b").string(),
                                  "--linear", "40/1", "--classical", "0.05", "--spp", spp,
                                  "--reference-noise", "0.05", "--reference-max-spp", "64", "--max-edge", "140"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }

  static std::filesystem::path* dir_;
};

std::filesystem::path* BenchCommand::dir_ = nullptr;

bool is_png(const std::filesystem::path& file) {
  const std::string bytes = test::read_text(file);
  return bytes.size() > 800 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

TEST_F(BenchCommand, SweepsWritesTheDocumentedCsvAndChartsThenResumes) {
  const std::filesystem::path out = *dir_ / "b";
  const auto first = test::run_lhr(bench_args());
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.err.find("[1/4] linear eps_link=40 eps_pixel=1 ... "), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("% within 10 %"), std::string::npos) << first.err;

  const std::string csv = test::read_text(out / "bench.csv");
  const auto lines = split(csv, '\n');
  ASSERT_EQ(lines.size(), 6u) << csv;  // header, four runs, the end of the last line
  EXPECT_EQ(lines[0], kDocumentedHeader);
  const std::vector<std::string> methods{"linear", "classical", "path", "path"};
  const auto column = [](const std::string& name) { return static_cast<std::size_t>(bench_csv_column(name) - 1); };
  for (std::size_t i = 0; i < methods.size(); ++i) {
    SCOPED_TRACE(lines[i + 1]);
    const auto cells = split(lines[i + 1], ',');
    ASSERT_EQ(cells.size(), bench_csv_columns().size());
    EXPECT_EQ(cells[0], methods[i]);
    for (const char* metric : {"rel_within_10", "rel_within_15", "within_10", "within_15"}) {
      const double v = std::stod(cells[column(metric)]);
      EXPECT_TRUE(std::isfinite(v) && v >= 0.0 && v <= 100.0) << metric << " " << v;
    }
    EXPECT_LE(std::stod(cells[column("rel_within_10")]), std::stod(cells[column("rel_within_15")]));
    const double ratio = std::stod(cells[column("mean_ratio")]);
    EXPECT_TRUE(std::isfinite(ratio) && ratio > 0.0) << ratio;
    EXPECT_GT(std::stod(cells[column("seconds_total")]), 0.0);
    EXPECT_GT(std::stod(cells[column("peak_rss_bytes")]), 1e6);
    EXPECT_EQ(cells[column("links")].empty(), methods[i] == "path");
    EXPECT_EQ(cells[column("graph_bytes")].empty(), methods[i] != "linear");
  }
  // The finer path image is closer to the reference.
  EXPECT_GT(std::stod(split(lines[4], ',')[column("within_15")]),
            std::stod(split(lines[3], ',')[column("within_15")]) - 1e-9);

  for (const char* chart : {"accuracy_vs_links.png", "accuracy_vs_seconds.png", "accuracy_vs_memory.png",
                            "reference.png"}) {
    EXPECT_TRUE(is_png(out / chart)) << chart;
  }
  EXPECT_TRUE(std::filesystem::exists(out / "charts.gp"));
  EXPECT_TRUE(std::filesystem::exists(out / "reference.exr"));
  EXPECT_TRUE(std::filesystem::exists(out / "runs" / "linear-40-1" / "row.json"));
  // Seconds to reach the default targets (90 and 95 %), each method side by side.
  const auto reach = split(test::read_text(out / "reach.csv"), '\n');
  ASSERT_EQ(reach.size(), 8u);  // header, 2 targets x 3 methods, the end of the last line
  for (std::size_t k = 1; k < 7; ++k) {
    EXPECT_EQ(split(reach[k], ',')[1], methods[std::min<std::size_t>((k - 1) % 3, 2)]) << reach[k];
  }
  EXPECT_NE(first.err.find("lhr bench: 90 % within 10 %: linear "), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("lhr bench: 95 % within 10 %: linear "), std::string::npos) << first.err;

  // The same command again runs nothing and writes the same table.
  std::vector<std::filesystem::file_time_type> written;
  for (const char* run : {"linear-40-1", "classical-0.05", "path-4", "path-16"}) {
    written.push_back(std::filesystem::last_write_time(out / "runs" / run / "row.json"));
  }
  const auto again = test::run_lhr(bench_args());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.err.find(" ... "), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("[4/4] path spp=16: done earlier"), std::string::npos) << again.err;
  EXPECT_EQ(test::read_text(out / "bench.csv"), csv);
  std::size_t i = 0;
  for (const char* run : {"linear-40-1", "classical-0.05", "path-4", "path-16"}) {
    EXPECT_EQ(std::filesystem::last_write_time(out / "runs" / run / "row.json"), written[i++]) << run;
  }

  // A time limit already spent starts nothing new and says what was left.
  const auto limited = test::run_lhr(bench_args("4,16,32", {"--max-seconds", "0.000001"}));
  ASSERT_EQ(limited.exit_code, 0) << limited.err;
  EXPECT_NE(limited.err.find("not run (1): path spp=32"), std::string::npos) << limited.err;
  EXPECT_EQ(test::read_text(out / "bench.csv"), csv);
  EXPECT_FALSE(std::filesystem::exists(out / "runs" / "path-32"));

  // Metrics are not stored with a run but scored again from its image on
  // every resume, so rows finished before a metric existed get it: a run's
  // image made twice as bright (exact in the EXR's half floats) shows as a
  // mean ratio twice as large.
  const std::filesystem::path run = out / "runs" / "classical-0.05";
  const nlohmann::json record = nlohmann::json::parse(test::read_text(run / "row.json"));
  for (const auto& [key, value] : record.items()) {
    EXPECT_TRUE(key == "arguments" || key == "seconds_total" || key == "peak_rss_bytes" || key == "stats") << key;
  }
  Image image = read_image(run / "image.exr");
  for (float& v : image.rgb) v *= 2.0f;
  write_image(run / "image.exr", image);
  const auto rescored = test::run_lhr(bench_args());
  ASSERT_EQ(rescored.exit_code, 0) << rescored.err;
  EXPECT_EQ(rescored.err.find(" ... "), std::string::npos) << rescored.err;
  const auto before = split(lines[2], ','), after = split(split(test::read_text(out / "bench.csv"), '\n')[2], ',');
  ASSERT_EQ(after[0], "classical");
  EXPECT_NEAR(std::stod(after[column("mean_ratio")]), 2.0 * std::stod(before[column("mean_ratio")]), 2e-6);
  EXPECT_EQ(after[column("links")], before[column("links")]);
}

TEST_F(BenchCommand, WithoutGnuplotWritesTheScriptAndWarnsOnce) {
  const std::filesystem::path out = *dir_ / "g";
  const std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", (*dir_ / "empty").c_str(), 1);
  auto args = bench_args("4", {"--methods", "path"});
  args[3] = out.string();
  const auto r = test::run_lhr(args);
  setenv("PATH", path.c_str(), 1);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto warning = r.err.find("warning: gnuplot is not on PATH");
  EXPECT_NE(warning, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("warning: gnuplot", warning + 1), std::string::npos) << "warned once: " << r.err;
  EXPECT_EQ(split(test::read_text(out / "bench.csv"), '\n').size(), 3u);
  EXPECT_EQ(split(test::read_text(out / "reach.csv"), '\n').size(), 4u);  // header, 90 and 95 for the path tracer
  EXPECT_TRUE(std::filesystem::exists(out / "charts.gp"));
  EXPECT_FALSE(std::filesystem::exists(out / "accuracy_vs_seconds.png"));
}

// The sweep's own code on the smallest plan, fast enough to run sanitized
// (SweepsWritesTheDocumentedCsvAndChartsThenResumes checks its numbers on a
// larger one, in release only): a classical run and a path-traced one, the
// charts drawn by gnuplot, a second command that reuses both runs and the
// reference, and a time limit already spent.
TEST_F(BenchCommand, ASmallSweepDrawsItsChartsReusesItsRunsAndKeepsItsTimeLimit) {
  const std::filesystem::path out = *dir_ / "s";
  const auto args = [&](const std::string& spp, std::vector<std::string> extra) {
    std::vector<std::string> a{"bench", (*dir_ / "tiny.scene.json").string(), "--out", out.string(), "--methods",
                               "classical,path", "--classical", "0.5", "--spp", spp, "--reference-noise", "0.05",
                               "--reference-max-spp", "16", "--max-edge", "140"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const auto first = test::run_lhr(args("4", {}));
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.err.find("[1/2] classical eps_bf=0.5 ... "), std::string::npos) << first.err;
  const std::string csv = test::read_text(out / "bench.csv");
  EXPECT_EQ(split(csv, '\n').size(), 4u) << csv;  // header, two runs, the end of the last line
  for (const char* chart : {"accuracy_vs_links.png", "accuracy_vs_seconds.png", "accuracy_vs_memory.png"}) {
    EXPECT_TRUE(is_png(out / chart)) << chart;
  }
  const auto again = test::run_lhr(args("4", {}));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.err.find(" ... "), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("[2/2] path spp=4: done earlier"), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("(made earlier; delete it for a new one)"), std::string::npos) << again.err;
  EXPECT_EQ(test::read_text(out / "bench.csv"), csv);
  const auto limited = test::run_lhr(args("4,8", {"--max-seconds", "0.000001"}));
  ASSERT_EQ(limited.exit_code, 0) << limited.err;
  EXPECT_NE(limited.err.find("not run (1): path spp=8"), std::string::npos) << limited.err;
  EXPECT_FALSE(std::filesystem::exists(out / "runs" / "path-8"));
}

TEST_F(BenchCommand, HelpDocumentsEveryColumnAndBadListsFailInOneLine) {
  const auto help = test::run_lhr({"bench", "--help"});
  ASSERT_EQ(help.exit_code, 0);
  for (const std::string& c : bench_csv_columns()) EXPECT_NE(help.out.find(c), std::string::npos) << c;
  const auto bad = test::run_lhr({"bench", (*dir_ / "tiny.scene.json").string(), "--out", (*dir_ / "x").string(),
                                  "--linear", "10:0.3"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(test::count_lines(bad.err), 1) << bad.err;
  EXPECT_NE(bad.err.find("--linear: \"10:0.3\""), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(*dir_ / "x"));
}

}  // namespace
}  // namespace lhr
