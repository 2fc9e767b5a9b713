#pragma once
// Line charts of a CSV file through gnuplot: the script is a file of its
// own beside the CSV (anyone can edit and rerun it), and drawing it writes
// PNGs atomically. `lhr bench` draws its accuracy charts with it.

#include <filesystem>
#include <string>
#include <vector>

namespace lhr {

// The CSV rows whose key column equals key, drawn as one curve.
struct ChartSeries {
  std::string key;
  std::string title;
};

// One panel: a y column against the chart's x column.
struct ChartPanel {
  int y_column = 0;  // 1-based
  std::string title;
  std::string y_label;
  std::string y_range = "[*:*]";  // gnuplot's syntax, e.g. "[*:100]"
  std::string key = "bottom right";  // where the legend goes
  std::vector<double> y_lines;       // a dashed horizontal line at each y (the ideal value, a target)
};

struct Chart {
  std::string file;   // PNG name, in the script's directory
  std::string title;  // above the panels
  int x_column = 0;   // 1-based
  double x_divisor = 1.0;
  std::string x_label;
  bool log_x = true;
  std::string x_format = "%g";  // gnuplot tic format, e.g. "10^{%T}"
  std::vector<ChartSeries> series;
  std::vector<ChartPanel> panels;  // left to right, then top to bottom
  int panels_per_row = 0;          // 0: all in one row
};

// A gnuplot script drawing the charts from csv_file (a name relative to the
// script's directory, header on its first line). The PNG terminal is
// pngcairo where gnuplot has it, else png. Points of a curve are joined in
// order of x. Every series must have at least one row.
std::string gnuplot_script(const std::string& csv_file, int key_column, const std::vector<Chart>& charts);

// Runs gnuplot on the script in the script's directory. The PNGs are drawn
// under temporary names and renamed once all are drawn. Returns false, doing
// nothing, when gnuplot is not on PATH; throws std::runtime_error naming the
// script and gnuplot's last message when it fails.
bool draw_charts(const std::filesystem::path& script, const std::vector<Chart>& charts);

}  // namespace lhr
