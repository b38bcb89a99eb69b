#include "plot.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

extern char** environ;

namespace podid::cli {
namespace {

// gnuplot single-quoted string: '' stands for one quote.
std::string Quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

std::string Substitute(std::string script, const std::vector<std::string>& paths) {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::string key = "{data" + std::to_string(i) + "}";
    for (std::size_t at = script.find(key); at != std::string::npos;
         at = script.find(key, at + 1)) {
      script.replace(at, key.size(), Quote(paths[i]));
    }
  }
  return script;
}

std::string Header(const PlotRequest& r, const std::string& png) {
  std::ostringstream os;
  os << "set terminal pngcairo size " << r.width_px << "," << r.height_px
     << " noenhanced font 'sans,10'\n"
     << "set output " << Quote(png) << "\n";
  return os.str();
}

void WriteFile(const std::string& path, const std::function<void(std::ostream&)>& write) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("plot: cannot write temporary file " + path);
  out.precision(10);
  write(out);
  out.flush();
  if (!out) throw std::runtime_error("plot: error writing temporary file " + path);
}

std::string AxesScript(const Axes& axes) {
  std::ostringstream os;
  if (!axes.title.empty()) os << "set title " << Quote(axes.title) << "\n";
  os << "set xlabel " << Quote(axes.x_label) << "\nset ylabel " << Quote(axes.y_label) << "\n";
  if (axes.log_y) os << "set logscale y\nset format y \"%.0e\"\n";
  os << "set grid\n";
  return os.str();
}

}  // namespace

std::string FindGnuplot() {
  if (const char* explicit_path = std::getenv("PODID_GNUPLOT"); explicit_path != nullptr) {
    return access(explicit_path, X_OK) == 0 ? std::string(explicit_path) : std::string();
  }
  const char* path = std::getenv("PATH");
  if (path == nullptr) return {};
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/gnuplot";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

PlotOutcome RenderPlot(const PlotRequest& request) {
  if (request.output_png.empty()) ThrowInvalid("plot", "an output PNG path", "\"\"");
  const std::string& png = request.output_png;
  const std::string gnuplot = FindGnuplot();
  if (gnuplot.empty()) {
    std::vector<std::string> paths;
    for (std::size_t i = 0; i < request.data.size(); ++i) {
      paths.push_back(png + ".data" + std::to_string(i) + ".txt");
      WriteFileAtomically(paths.back(), [&](std::ostream& os) {
        os.precision(10);
        request.data[i](os);
      });
    }
    const std::string script = png + ".gp";
    WriteFileAtomically(script, [&](std::ostream& os) {
      os << Header(request, png) << Substitute(request.script, paths);
    });
    std::fprintf(stderr,
                 "podid: gnuplot not found on PATH: %s not drawn; wrote %s and its data "
                 "(run 'gnuplot %s')\n",
                 png.c_str(), script.c_str(), script.c_str());
    return PlotOutcome::kNoGnuplot;
  }

  const std::string stem = png + ".tmp" + std::to_string(getpid());
  std::vector<std::string> temporaries;
  const auto cleanup = [&] {
    std::error_code ignored;
    for (const auto& t : temporaries) std::filesystem::remove(t, ignored);
  };
  try {
    std::vector<std::string> paths;
    for (std::size_t i = 0; i < request.data.size(); ++i) {
      paths.push_back(stem + ".data" + std::to_string(i));
      temporaries.push_back(paths.back());
      WriteFile(paths.back(), request.data[i]);
    }
    const std::string script = stem + ".gp", image = stem + ".png";
    temporaries.push_back(script);
    temporaries.push_back(image);
    WriteFile(script, [&](std::ostream& os) {
      os << Header(request, image) << Substitute(request.script, paths) << "\nunset output\n";
    });
    std::vector<char*> argv = {const_cast<char*>(gnuplot.c_str()),
                               const_cast<char*>(script.c_str()), nullptr};
    pid_t pid = 0;
    if (posix_spawn(&pid, gnuplot.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
      throw std::runtime_error("plot: cannot run " + gnuplot);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      throw std::runtime_error("plot: gnuplot failed drawing " + png);
    }
    std::error_code error;
    if (!std::filesystem::exists(image) || std::filesystem::file_size(image, error) == 0) {
      throw std::runtime_error("plot: gnuplot wrote no image for " + png);
    }
    std::filesystem::rename(image, png, error);
    if (error) throw std::runtime_error("plot: cannot rename onto " + png + ": " + error.message());
  } catch (...) {
    cleanup();
    throw;
  }
  cleanup();
  return PlotOutcome::kWritten;
}

PlotOutcome PlotLines(const std::string& output_png,
                      const Axes& axes,
                      const std::vector<LineSeries>& series) {
  PlotRequest r;
  r.output_png = output_png;
  std::ostringstream script;
  script << AxesScript(axes) << "set key outside bottom center horizontal\nplot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const LineSeries& s = series[i];
    PODID_CHECK(s.x.size() == s.y.size());
    r.data.push_back([&s](std::ostream& os) {
      for (Eigen::Index k = 0; k < s.x.size(); ++k) os << s.x(k) << ' ' << s.y(k) << '\n';
    });
    script << (i ? ", " : "") << "{data" << i << "} using 1:2 with lines lw 1.5 title "
           << Quote(s.title);
  }
  script << "\n";
  r.script = script.str();
  return RenderPlot(r);
}

PlotOutcome PlotHeatMap(const std::string& output_png,
                        const Axes& axes,
                        const std::string& z_label,
                        const Eigen::VectorXd& x,
                        const Eigen::VectorXd& y,
                        const Eigen::MatrixXd& z,
                        const std::vector<LineSeries>& overlay) {
  PODID_CHECK(z.rows() == x.size() && z.cols() == y.size());
  PlotRequest r;
  r.output_png = output_png;
  // pm3d map: one block per x, blank lines between blocks (non-uniform y is fine).
  r.data.push_back([&](std::ostream& os) {
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      for (Eigen::Index j = 0; j < y.size(); ++j)
        os << x(i) << ' ' << y(j) << ' ' << z(i, j) << '\n';
      os << '\n';
    }
  });
  const double top = z.size() > 0 ? z.maxCoeff() : 0.0;
  std::ostringstream script;
  script << AxesScript(axes) << "unset grid\nset view map\nset pm3d map corners2color c1\n"
         << "set palette rgbformulae 30,31,32\nset cblabel " << Quote(z_label) << "\n"
         << "set xrange [" << x.minCoeff() << ":" << x.maxCoeff() << "]\n"
         << "set yrange [" << y.minCoeff() << ":" << y.maxCoeff() << "]\n"
         << "set key outside bottom center horizontal\n"
         << "splot {data0} using 1:2:3 with pm3d notitle";
  for (std::size_t i = 0; i < overlay.size(); ++i) {
    const LineSeries& s = overlay[i];
    PODID_CHECK(s.x.size() == s.y.size());
    r.data.push_back([&s](std::ostream& os) {
      for (Eigen::Index k = 0; k < s.x.size(); ++k) {
        if (std::isfinite(s.y(k))) {
          os << s.x(k) << ' ' << s.y(k) << '\n';
        } else {
          os << '\n';
        }
      }
    });
    script << ", {data" << (i + 1) << "} using 1:2:(" << top
           << ") with lines lw 2 lc rgb 'white' title " << Quote(s.title);
  }
  script << "\n";
  r.script = script.str();
  return RenderPlot(r);
}

}  // namespace podid::cli
