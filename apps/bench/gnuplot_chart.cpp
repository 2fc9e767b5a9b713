#include "apps/bench/gnuplot_chart.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "apps/bench/child_process.hpp"

namespace lhr {

namespace {

// A gnuplot single-quoted string: no escapes but '' for a quote.
std::string quoted(const std::string& text) {
  std::string q = "'";
  for (const char c : text) {
    if (c == '\'') q += "''";
    else q += c;
  }
  return q + "'";
}

constexpr const char* kTemporaryPrefix = ".tmp-";

const char* const kLineStyles[] = {
    "lc rgb '#1f4e9c' lw 2 pt 7 ps 1.3",   // blue, filled circles
    "lc rgb '#c0392b' lw 2 pt 5 ps 1.3",   // red, filled squares
    "lc rgb '#2e8b57' lw 2 pt 9 ps 1.5",   // green, filled triangles
    "lc rgb '#7d3c98' lw 2 pt 13 ps 1.4",  // purple, filled diamonds
};


}  // namespace

std::string gnuplot_script(const std::string& csv_file, int key_column, const std::vector<Chart>& charts) {
  std::ostringstream s;
  s << "# Charts of " << csv_file << ": run 'gnuplot " << "charts.gp' in this directory to redraw them.\n"
    << "set datafile separator ','\n"
    << "if (!exists('out_prefix')) out_prefix = ''\n"
    << "cairo = strstrt(GPVAL_TERMINALS, 'pngcairo') > 0\n"
    << "set grid\n";
  for (std::size_t i = 0; i < std::size(kLineStyles); ++i) {
    s << "set style line " << i + 1 << " " << kLineStyles[i] << "\n";
  }
  for (const Chart& chart : charts) {
    const std::size_t per_row = chart.panels_per_row > 0 ? static_cast<std::size_t>(chart.panels_per_row)
                                                         : std::max<std::size_t>(1, chart.panels.size());
    const std::size_t rows = std::max<std::size_t>(1, (chart.panels.size() + per_row - 1) / per_row);
    const std::string size = std::to_string(500 * per_row) + "," + std::to_string(480 * rows);
    s << "\n# " << chart.file << "\n"
      << "if (cairo) {\n"
      << "  set terminal pngcairo enhanced size " << size << " font 'sans,10'\n"
      << "} else {\n"
      << "  set terminal png enhanced size " << size << "\n"
      << "}\n"
      << "set output out_prefix." << quoted(chart.file) << "\n"
      << "set multiplot layout " << rows << "," << per_row << " title " << quoted(chart.title) << " noenhanced\n"
      << (chart.log_x ? "set logscale x\n" : "unset logscale x\n") << "set format x " << quoted(chart.x_format)
      << "\n"
      << "set xlabel " << quoted(chart.x_label) << " noenhanced\n";
    for (const ChartPanel& panel : chart.panels) {
      s << "set yrange " << panel.y_range << "\n"
        << "set key " << panel.key << "\n"
        << "set title " << quoted(panel.title) << " noenhanced\n"
        << "set ylabel " << quoted(panel.y_label) << " noenhanced\n";
      s << "unset arrow\n";
      if (!panel.y_lines.empty()) {
        // An arrow spans the whole width; the undrawn functions keep the
        // lines' y inside the autoscaled range, the offsets off the border.
        s << "set offsets 0, 0, graph 0.05, graph 0.05\n";
        std::ostringstream plot;
        for (std::size_t k = 0; k < panel.y_lines.size(); ++k) {
          std::ostringstream y;
          y << std::setprecision(15) << panel.y_lines[k];
          s << "set arrow " << k + 1 << " from graph 0, first " << y.str() << " to graph 1, first " << y.str()
            << " nohead dt 2 lc rgb '#808080'\n";
          plot << " " << y.str() << " with lines lt nodraw notitle,";
        }
        s << "plot" << plot.str();
      } else {
        s << "set offsets 0, 0, 0, 0\nplot";
      }
      for (std::size_t i = 0; i < chart.series.size(); ++i) {
        const ChartSeries& series = chart.series[i];
        std::ostringstream x;
        x << std::setprecision(15) << "$" << chart.x_column;
        if (chart.x_divisor != 1.0) x << "/" << chart.x_divisor;
        // Other series' rows become NaN, which gnuplot leaves out; smooth
        // unique joins the points in order of x.
        s << (i ? ", \\\n    " : " ") << quoted(csv_file) << " skip 1 using ((strcol(" << key_column
          << ") eq " << quoted(series.key) << ") ? " << x.str() << " : NaN):" << panel.y_column
          << " smooth unique with linespoints ls " << i % std::size(kLineStyles) + 1 << " title "
          << quoted(series.title) << " noenhanced";
      }
      s << "\n";
    }
    s << "unset multiplot\nset output\n";
  }
  return s.str();
}

bool draw_charts(const std::filesystem::path& script, const std::vector<Chart>& charts) {
  if (!find_on_path("gnuplot")) return false;
  const std::filesystem::path dir = script.has_parent_path() ? script.parent_path() : std::filesystem::path(".");
  const std::filesystem::path log = dir / ".charts.log";
  const auto remove_temporaries = [&] {
    std::error_code ignored;
    for (const Chart& chart : charts) std::filesystem::remove(dir / (kTemporaryPrefix + chart.file), ignored);
    std::filesystem::remove(log, ignored);
  };
  ChildOptions options;
  options.log = log;
  options.working_dir = dir;
  const ChildResult r =
      run_child("gnuplot", {"-e", std::string("out_prefix='") + kTemporaryPrefix + "'", script.filename().string()},
                options);
  if (r.exit_code != 0) {
    // gnuplot ends with the error, after echoing the line it stopped at.
    const std::string message = last_log_line(log);
    remove_temporaries();
    throw std::runtime_error(script.string() + ": gnuplot failed: " + message);
  }
  for (const Chart& chart : charts) {
    std::error_code ec;
    std::filesystem::rename(dir / (kTemporaryPrefix + chart.file), dir / chart.file, ec);
    if (ec) {
      remove_temporaries();
      throw std::runtime_error((dir / chart.file).string() + ": gnuplot drew no chart: " + ec.message());
    }
  }
  remove_temporaries();
  return true;
}

}  // namespace lhr
