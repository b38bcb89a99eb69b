#pragma once
// Plots for the podid commands, drawn by gnuplot (Debian's gnuplot-nox).
//
// RenderPlot() writes each data file and the script to temporaries next to
// the PNG, runs `gnuplot SCRIPT`, and renames the temporary PNG onto the
// requested path, so an error never leaves a partial PNG. The temporaries are
// removed afterwards.
//
// Without gnuplot on PATH (or $PODID_GNUPLOT, an explicit program path) it
// says so on stderr, keeps the data and the script next to the PNG instead
// (<png>.gp, <png>.data0.txt, ...; run `gnuplot <png>.gp` later) and returns
// PlotOutcome::kNoGnuplot; the command still writes its other outputs.
//
// Usage (a generic script body; {data0}, {data1}, ... become the quoted data
// file paths; the terminal and output lines are added):
//   PlotRequest r;
//   r.output_png = "fit.png";
//   r.data.push_back([&](std::ostream& os) { for (...) os << t << ' ' << y << '\n'; });
//   r.script = "set xlabel 't (s)'\nplot {data0} using 1:2 with lines title 'y'\n";
//   RenderPlot(r);
// PlotLines() and PlotHeatMap() build such requests for the common cases.

#include <Eigen/Core>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace podid::cli {

enum class PlotOutcome {
  kWritten,    ///< the PNG was drawn
  kNoGnuplot,  ///< gnuplot not found: script and data kept next to the PNG
};

struct PlotRequest {
  std::string output_png;  ///< final PNG path
  std::string script;      ///< gnuplot commands; {dataN} = quoted path of data[N]
  std::vector<std::function<void(std::ostream&)>> data;  ///< writers of the data files
  int width_px = 1000;
  int height_px = 650;
};

/// Draws the plot. Throws std::runtime_error if gnuplot runs and fails (its
/// stderr is passed through) and std::invalid_argument for an empty path.
PlotOutcome RenderPlot(const PlotRequest& request);

/// One curve: y (dim n) against x (dim n).
struct LineSeries {
  std::string title;
  Eigen::VectorXd x;
  Eigen::VectorXd y;
};

struct Axes {
  std::string title;
  std::string x_label;  ///< with units, e.g. "t (s)"
  std::string y_label;
  bool log_y = false;
};

/// Curves on one set of axes.
PlotOutcome PlotLines(const std::string& output_png,
                      const Axes& axes,
                      const std::vector<LineSeries>& series);

/// A colour map z(x_i, y_j) (z: x.size() x y.size(); x and y ascending, y may
/// be non-uniform, e.g. log-spaced frequencies) with optional curves on top.
PlotOutcome PlotHeatMap(const std::string& output_png,
                        const Axes& axes,
                        const std::string& z_label,
                        const Eigen::VectorXd& x,
                        const Eigen::VectorXd& y,
                        const Eigen::MatrixXd& z,
                        const std::vector<LineSeries>& overlay = {});

/// The gnuplot program that RenderPlot would run, or "" if there is none.
std::string FindGnuplot();

}  // namespace podid::cli
