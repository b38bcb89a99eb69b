#pragma once
// Plots for the podid commands, drawn by gnuplot (Debian's gnuplot-nox).
//
// RenderPlot() writes each data file and the script under fixed names
// (data0, data1, ..., plot.gp) in a private folder (mkdtemp, mode 0700, in
// $TMPDIR or /tmp), runs gnuplot there without a shell (posix_spawn, argv
// {gnuplot, "plot.gp"}), and copies the image it draws there (plot.png) to the
// requested path with WriteFileAtomically, so an error never leaves a partial
// PNG and the PNG follows the rules of every other output (symlinks written
// through, devices in place). The folder is removed afterwards, and on
// SIGINT/SIGTERM/SIGHUP. No user path appears in the script; every user text
// in it (titles, labels, curve names) is an escaped gnuplot string (see
// GnuplotString in plot.cpp): it cannot end the string or run a command.
//
// Without gnuplot on PATH (or $PODID_GNUPLOT, an explicit program path) it
// says so on stderr, keeps the data and the script in a new folder next to
// the PNG instead (<png>.gnuplot-XXXXXX/plot.gp, data0.txt, ...; run `gnuplot
// <that folder>/plot.gp` later from the same folder; the paths in it are
// escaped the same way) and returns PlotOutcome::kNoGnuplot; the command
// still writes its other outputs. With PlotRequest::batch (or the batch
// argument of PlotLines and PlotHeatMap) the PNG is staged in the command's
// OutputBatch, so a gnuplot failing later leaves none of its files.
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

#include "podid/core/io.hpp"

namespace podid::cli {

enum class PlotOutcome {
  kWritten,    ///< the PNG was drawn
  kNoGnuplot,  ///< gnuplot not found: script and data kept next to the PNG
};

struct PlotRequest {
  std::string output_png;  ///< final PNG path
  std::string script;      ///< gnuplot commands; {dataN} = quoted name of data[N]
  std::vector<std::function<void(std::ostream&)>> data;  ///< writers of the data files
  int width_px = 1000;
  int height_px = 650;
  /// If set, the PNG (without gnuplot: the kept folder's script and data) is
  /// staged in it, published by its Commit, instead of written at once.
  OutputBatch* batch = nullptr;
};

/// Draws the plot. Throws std::runtime_error if gnuplot runs and fails (the
/// message gives gnuplot's reason; its output never reaches the terminal
/// raw, its warnings on success become "podid: note: gnuplot, ..." lines) and
/// std::invalid_argument for an empty path.
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
                      const std::vector<LineSeries>& series,
                      OutputBatch* batch = nullptr);

/// A colour map z(x_i, y_j) (z: x.size() x y.size(); x and y ascending, y may
/// be non-uniform, e.g. log-spaced frequencies) with optional curves on top.
PlotOutcome PlotHeatMap(const std::string& output_png,
                        const Axes& axes,
                        const std::string& z_label,
                        const Eigen::VectorXd& x,
                        const Eigen::VectorXd& y,
                        const Eigen::MatrixXd& z,
                        const std::vector<LineSeries>& overlay = {},
                        OutputBatch* batch = nullptr);

/// The gnuplot program that RenderPlot would run, or "" if there is none.
std::string FindGnuplot();

}  // namespace podid::cli
