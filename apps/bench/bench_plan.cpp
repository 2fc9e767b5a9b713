#include "apps/bench/bench_plan.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

namespace lhr {

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// Comma-separated items, trimmed; an empty list or item is an error.
std::vector<std::string> split_list(const std::string& text, const std::string& option) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = trim(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (item.empty()) throw std::invalid_argument(option + ": empty item in \"" + text + "\"");
    items.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

std::optional<double> parse_positive(const std::string& text) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value) || !(value > 0.0)) return std::nullopt;
  return value;
}

void reject_duplicates(const std::vector<BenchRun>& runs, const std::string& option) {
  std::set<std::string> seen;
  for (const BenchRun& run : runs) {
    if (!seen.insert(run.id()).second) throw std::invalid_argument(option + " lists " + run.label() + " twice");
  }
}

// One run per item of an option's list, none twice.
template <typename ParseItem>
std::vector<BenchRun> parse_runs(const std::string& text, const std::string& option, ParseItem parse_item) {
  std::vector<BenchRun> runs;
  for (const std::string& item : split_list(text, option)) runs.push_back(parse_item(item));
  reject_duplicates(runs, option);
  return runs;
}

// Fixed decimals for a CSV cell.
std::string fixed(double value, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << value;
  return s.str();
}

// Cells read from a record: empty when the run's method has no such value.
std::string count_cell(const nlohmann::json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_number()) return "";
  return std::to_string(object[key].get<long long>());
}

// numerator[key] per link of the run's stats: empty without links (the path
// tracer) or without the value.
std::string per_link_cell(const nlohmann::json& numerator, const char* key, const nlohmann::json& stats) {
  if (!numerator.is_object() || !numerator.contains(key) || !numerator[key].is_number()) return "";
  if (!stats.is_object() || !stats.contains("links") || !stats["links"].is_number()) return "";
  const double links = stats["links"].get<double>();
  return links > 0 ? fixed(numerator[key].get<double>() / links, 1) : "";
}

std::string seconds_cell(const nlohmann::json& object, const char* key) {
  if (!object.is_object() || !object.contains(key) || !object[key].is_number()) return "";
  return fixed(object[key].get<double>(), 3);
}

// Phases of stats.json's "seconds" (either method; a method lacks some).
const char* const kPhases[] = {"meshing", "solve",   "linking",    "refine", "coefficients", "gather",
                               "push_pull", "oracles", "importance", "view", "output"};

}  // namespace

const char* bench_method_name(BenchMethod method) {
  switch (method) {
    case BenchMethod::kLinear: return "linear";
    case BenchMethod::kClassical: return "classical";
    case BenchMethod::kPath: return "path";
  }
  return "?";
}

std::string format_parameter(double value) {
  std::string s = fixed(value, 10);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

std::string BenchRun::id() const {
  switch (method) {
    case BenchMethod::kLinear: return "linear-" + format_parameter(eps_link) + "-" + format_parameter(eps_pixel);
    case BenchMethod::kClassical: return "classical-" + format_parameter(eps_bf);
    case BenchMethod::kPath: return "path-" + std::to_string(spp);
  }
  return "?";
}

std::string BenchRun::label() const {
  switch (method) {
    case BenchMethod::kLinear:
      return "eps_link=" + format_parameter(eps_link) + " eps_pixel=" + format_parameter(eps_pixel);
    case BenchMethod::kClassical: return "eps_bf=" + format_parameter(eps_bf);
    case BenchMethod::kPath: return "spp=" + std::to_string(spp);
  }
  return "?";
}

std::vector<BenchRun> parse_linear_list(const std::string& text) {
  return parse_runs(text, "--linear", [](const std::string& item) {
    const std::size_t slash = item.find('/');
    const auto link = slash == std::string::npos ? std::nullopt : parse_positive(trim(item.substr(0, slash)));
    const auto pixel = slash == std::string::npos ? std::nullopt : parse_positive(trim(item.substr(slash + 1)));
    if (!link || !pixel) {
      throw std::invalid_argument("--linear: \"" + item +
                                  "\" is not eps_link/eps_pixel with two positive numbers (e.g. 10/0.3)");
    }
    BenchRun run;
    run.method = BenchMethod::kLinear;
    run.eps_link = *link;
    run.eps_pixel = *pixel;
    return run;
  });
}

std::vector<BenchRun> parse_classical_list(const std::string& text) {
  return parse_runs(text, "--classical", [](const std::string& item) {
    const auto eps = parse_positive(item);
    if (!eps) throw std::invalid_argument("--classical: \"" + item + "\" is not a positive eps_bf (e.g. 0.003)");
    BenchRun run;
    run.method = BenchMethod::kClassical;
    run.eps_bf = *eps;
    return run;
  });
}

std::vector<BenchRun> parse_spp_list(const std::string& text) {
  return parse_runs(text, "--spp", [](const std::string& item) {
    int spp = 0;
    const char* end = item.data() + item.size();
    const auto [ptr, ec] = std::from_chars(item.data(), end, spp);
    // Two samples at least: lhr reference estimates its noise from two halves.
    if (ec != std::errc() || ptr != end || spp < 2) {
      throw std::invalid_argument("--spp: \"" + item + "\" is not a whole number of samples per pixel of at least 2");
    }
    BenchRun run;
    run.method = BenchMethod::kPath;
    run.spp = spp;
    return run;
  });
}

std::vector<BenchMethod> parse_method_list(const std::string& text) {
  std::vector<BenchMethod> methods;
  for (const std::string& item : split_list(text, "--methods")) {
    BenchMethod method;
    if (item == "linear") method = BenchMethod::kLinear;
    else if (item == "classical") method = BenchMethod::kClassical;
    else if (item == "path") method = BenchMethod::kPath;
    else throw std::invalid_argument("--methods: \"" + item + "\" is not linear, classical or path");
    for (const BenchMethod m : methods) {
      if (m == method) throw std::invalid_argument("--methods lists " + item + " twice");
    }
    methods.push_back(method);
  }
  return methods;
}

std::vector<BenchRun> plan_bench(const std::vector<BenchMethod>& methods, const std::vector<BenchRun>& linear,
                                 const std::vector<BenchRun>& classical, const std::vector<BenchRun>& path) {
  const auto wanted = [&](BenchMethod m) {
    for (const BenchMethod x : methods) {
      if (x == m) return true;
    }
    return false;
  };
  std::vector<BenchRun> plan;
  if (wanted(BenchMethod::kLinear)) plan.insert(plan.end(), linear.begin(), linear.end());
  if (wanted(BenchMethod::kClassical)) plan.insert(plan.end(), classical.begin(), classical.end());
  if (wanted(BenchMethod::kPath)) plan.insert(plan.end(), path.begin(), path.end());
  return plan;
}

std::vector<std::string> bench_run_arguments(const BenchRun& run, const std::string& scene,
                                             const std::vector<std::string>& solve_arguments,
                                             const std::vector<std::string>& reference_arguments) {
  std::vector<std::string> args;
  switch (run.method) {
    case BenchMethod::kLinear:
      args = {"solve", scene, "--method", "linear", "--eps-link", format_parameter(run.eps_link),
              "--eps-pixel", format_parameter(run.eps_pixel)};
      break;
    case BenchMethod::kClassical:
      args = {"solve", scene, "--method", "classical", "--eps-bf", format_parameter(run.eps_bf)};
      break;
    case BenchMethod::kPath:
      args = {"reference", scene, "--spp", std::to_string(run.spp), "--seed", std::to_string(kPathRunSeed)};
      break;
  }
  const auto& shared = run.method == BenchMethod::kPath ? reference_arguments : solve_arguments;
  args.insert(args.end(), shared.begin(), shared.end());
  return args;
}

nlohmann::json bench_record(const std::vector<std::string>& arguments, double seconds_total,
                            std::size_t peak_rss_bytes, const nlohmann::json& stats) {
  return {{"arguments", arguments},
          {"seconds_total", seconds_total},
          {"peak_rss_bytes", peak_rss_bytes},
          {"stats", stats}};
}

const std::vector<std::string>& bench_csv_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c{"method", "parameters", "eps_link", "eps_pixel", "eps_bf", "spp",
                               "links",  "nodes",      "elements", "seconds_total"};
    for (const char* phase : kPhases) c.push_back(std::string("seconds_") + phase);
    for (const char* rest : {"peak_rss_bytes", "graph_bytes", "graph_overhead", "data_bytes_per_link",
                             "peak_rss_per_link", "rel_within_10", "rel_within_15",
                             "mean_ratio", "within_10", "within_15", "rmse", "psnr_db", "relative_error"}) {
      c.push_back(rest);
    }
    return c;
  }();
  return columns;
}

int bench_csv_column(const std::string& name) {
  const auto& columns = bench_csv_columns();
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i) + 1;
  }
  throw std::logic_error("bench.csv has no column " + name);
}

std::vector<Chart> bench_charts(const std::string& title, const std::vector<BenchRow>& rows,
                                const std::vector<double>& reach_targets) {
  const auto series_of = [&](bool with_path) {
    std::vector<ChartSeries> series;
    const std::pair<BenchMethod, const char*> methods[] = {
        {BenchMethod::kLinear, "linear HR"},
        {BenchMethod::kClassical, "classical HR"},
        {BenchMethod::kPath, "path tracer"}};
    for (const auto& [method, name] : methods) {
      if (method == BenchMethod::kPath && !with_path) continue;
      for (const BenchRow& row : rows) {
        if (row.run.method == method) {
          series.push_back({bench_method_name(method), name});
          break;
        }
      }
    }
    return series;
  };
  // docs/design.md §5: the relative luminance norm and the mean ratio are the
  // primary figures (top row); the paper's display-value norm saturates near
  // 100 % on dim tone-mapped images, so it and the RMSE of the display
  // values, which still separates the runs there, are secondary (bottom row).
  const std::vector<ChartPanel> panels{
      {bench_csv_column("rel_within_10"), "luminance within 10 % (primary)",
       "% of pixels with |Y - Y_ref| <= 10 % of Y_ref", "[*:100]", "bottom right", reach_targets},
      {bench_csv_column("rel_within_15"), "luminance within 15 % (primary)",
       "% of pixels with |Y - Y_ref| <= 15 % of Y_ref", "[*:100]", "bottom right", {}},
      {bench_csv_column("mean_ratio"), "mean ratio (1 is unbiased)", "mean Y / mean Y_ref", "[*:*]", "top right",
       {1.0}},
      {bench_csv_column("within_10"), "paper's display norm: within 10 %",
       "% of pixels within 10 % of the display range", "[*:100]", "bottom right", {}},
      {bench_csv_column("within_15"), "paper's display norm: within 15 %",
       "% of pixels within 15 % of the display range", "[*:100]", "bottom right", {}},
      {bench_csv_column("rmse"), "display RMSE (lower is better)", "RMS difference of the display values", "[0:*]",
       "top right", {}}};
  std::vector<Chart> charts;
  const auto add = [&](const std::string& file, const std::string& against, const std::string& column, double divisor,
                       const std::string& x_label, const std::string& x_format, bool with_path) {
    Chart chart;
    chart.file = file;
    chart.title = title + ": image accuracy against " + against;
    chart.x_column = bench_csv_column(column);
    chart.x_divisor = divisor;
    chart.x_label = x_label;
    chart.x_format = x_format;
    chart.series = series_of(with_path);
    chart.panels = panels;
    chart.panels_per_row = 3;
    if (!chart.series.empty()) charts.push_back(chart);
  };
  add("accuracy_vs_links.png", "links", "links", 1.0, "links (log scale)", "10^{%T}", false);
  add("accuracy_vs_seconds.png", "time", "seconds_total", 1.0,
      "seconds, wall clock of the whole run (log scale)", "%g", true);
  add("accuracy_vs_memory.png", "memory", "peak_rss_bytes", 1024.0 * 1024.0,
      "peak resident memory of the run, MiB (log scale)", "%g", true);
  return charts;
}

std::string bench_csv(const std::vector<BenchRow>& rows) {
  std::ostringstream out;
  const auto& columns = bench_csv_columns();
  for (std::size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
  out << "\n";
  for (const BenchRow& row : rows) {
    const BenchRun& run = row.run;
    const nlohmann::json& record = row.record;
    const nlohmann::json stats = record.contains("stats") ? record["stats"] : nlohmann::json();
    const nlohmann::json seconds = stats.is_object() && stats.contains("seconds") ? stats["seconds"] : nlohmann::json();
    const nlohmann::json bytes = stats.is_object() && stats.contains("bytes") ? stats["bytes"] : nlohmann::json();
    const bool linear = run.method == BenchMethod::kLinear;
    std::vector<std::string> cells{bench_method_name(run.method),
                                   run.label(),
                                   linear ? format_parameter(run.eps_link) : "",
                                   linear ? format_parameter(run.eps_pixel) : "",
                                   run.method == BenchMethod::kClassical ? format_parameter(run.eps_bf) : "",
                                   run.method == BenchMethod::kPath ? std::to_string(run.spp) : "",
                                   count_cell(stats, "links"),
                                   count_cell(stats, "nodes"),
                                   count_cell(stats, "elements"),
                                   seconds_cell(record, "seconds_total")};
    for (const char* phase : kPhases) cells.push_back(seconds_cell(seconds, phase));
    cells.push_back(count_cell(record, "peak_rss_bytes"));
    cells.push_back(count_cell(bytes, "graphs"));
    const bool overhead = bytes.is_object() && bytes.contains("graph_overhead");
    cells.push_back(overhead ? fixed(bytes["graph_overhead"].get<double>(), 4) : "");
    cells.push_back(per_link_cell(bytes, "total", stats));
    cells.push_back(per_link_cell(record, "peak_rss_bytes", stats));
    const ImageMetrics& m = row.metrics;
    cells.push_back(fixed(m.rel_within_10, 3));
    cells.push_back(fixed(m.rel_within_15, 3));
    cells.push_back(std::isfinite(m.mean_ratio) ? fixed(m.mean_ratio, 6) : "");
    cells.push_back(fixed(m.within_10, 3));
    cells.push_back(fixed(m.within_15, 3));
    cells.push_back(fixed(m.rmse, 6));
    cells.push_back(std::isfinite(m.psnr_db) ? fixed(m.psnr_db, 3) : "");
    cells.push_back(std::isfinite(m.relative_error) ? fixed(m.relative_error, 6) : "");
    for (std::size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << cells[i];
    out << "\n";
  }
  return out.str();
}

std::vector<double> parse_reach_list(const std::string& text) {
  std::vector<double> targets;
  for (const std::string& item : split_list(text, "--reach")) {
    const std::optional<double> target = parse_positive(item);
    if (!target || *target > 100.0) {
      throw std::invalid_argument("--reach: \"" + item + "\" is not a percentage in (0, 100]");
    }
    for (const double t : targets) {
      if (t == *target) throw std::invalid_argument("--reach lists " + item + " twice");
    }
    targets.push_back(*target);
  }
  return targets;
}

std::vector<BenchReach> bench_reach(const std::vector<BenchRow>& rows, const std::vector<double>& targets) {
  std::vector<BenchReach> reach;
  for (const double target : targets) {
    for (const BenchMethod method : {BenchMethod::kLinear, BenchMethod::kClassical, BenchMethod::kPath}) {
      BenchReach r;
      r.target = target;
      r.method = method;
      bool any = false;
      for (std::size_t i = 0; i < rows.size(); ++i) {
        if (rows[i].run.method != method) continue;
        any = true;
        const double within = rows[i].metrics.rel_within_10;
        r.best = std::max(r.best, within);
        if (!(within >= target)) continue;
        const auto seconds = [&](std::size_t k) { return rows[k].record["seconds_total"].get<double>(); };
        if (!r.row || seconds(i) < seconds(*r.row)) r.row = i;
      }
      if (any) reach.push_back(r);
    }
  }
  return reach;
}

namespace {

// The path tracer's seconds to the same target, when it got there.
std::optional<double> path_seconds(const std::vector<BenchRow>& rows, const std::vector<BenchReach>& reach,
                                   double target) {
  for (const BenchReach& r : reach) {
    if (r.target == target && r.method == BenchMethod::kPath && r.row) {
      return rows[*r.row].record["seconds_total"].get<double>();
    }
  }
  return std::nullopt;
}

}  // namespace

std::string reach_csv(const std::vector<BenchRow>& rows, const std::vector<BenchReach>& reach) {
  std::ostringstream out;
  out << "target,method,reached,seconds_total,parameters,rel_within_10,links,peak_rss_bytes,path_over_this\n";
  for (const BenchReach& r : reach) {
    out << format_parameter(r.target) << "," << bench_method_name(r.method) << "," << (r.row ? 1 : 0) << ",";
    if (r.row) {
      const BenchRow& row = rows[*r.row];
      const nlohmann::json stats = row.record.contains("stats") ? row.record["stats"] : nlohmann::json();
      const double seconds = row.record["seconds_total"].get<double>();
      const std::optional<double> path = path_seconds(rows, reach, r.target);
      out << seconds_cell(row.record, "seconds_total") << "," << row.run.label() << ","
          << fixed(row.metrics.rel_within_10, 3) << "," << count_cell(stats, "links") << ","
          << count_cell(row.record, "peak_rss_bytes") << ","
          << (path && seconds > 0.0 ? fixed(*path / seconds, 3) : "");
    } else {
      out << ",," << fixed(r.best, 3) << ",,,";
    }
    out << "\n";
  }
  return out.str();
}

std::vector<std::string> reach_summary(const std::vector<BenchRow>& rows, const std::vector<BenchReach>& reach) {
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < reach.size();) {
    const double target = reach[i].target;
    std::ostringstream line;
    line << format_parameter(target) << " % within 10 %:";
    std::ostringstream sooner;
    const std::optional<double> path = path_seconds(rows, reach, target);
    for (bool first = true; i < reach.size() && reach[i].target == target; ++i, first = false) {
      const BenchReach& r = reach[i];
      line << (first ? " " : ", ") << bench_method_name(r.method) << " ";
      if (!r.row) {
        line << "not reached (best " << fixed(r.best, 1) << " %)";
        continue;
      }
      const BenchRow& row = rows[*r.row];
      const double seconds = row.record["seconds_total"].get<double>();
      line << fixed(seconds, 1) << " s (" << row.run.label() << ")";
      if (path && r.method != BenchMethod::kPath && seconds > 0.0) {
        const bool sooner_than_path = *path >= seconds;
        sooner << "; " << bench_method_name(r.method) << " "
               << fixed(sooner_than_path ? *path / seconds : seconds / *path, 1)
               << (sooner_than_path ? "x sooner than" : "x slower than") << " the path tracer";
      }
    }
    lines.push_back(line.str() + sooner.str());
  }
  return lines;
}

}  // namespace lhr
