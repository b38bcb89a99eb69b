#include "plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/core/temp_files.hpp"

extern char** environ;

namespace podid::cli {
namespace {

// Every text podid puts in a gnuplot script (titles, labels, curve names from
// case files and data files, the paths of a kept script) goes through
// GnuplotString: a double-quoted gnuplot string in which every byte outside
// [A-Za-z0-9 ._,:/()=+-] is a three-digit octal escape (and so is an octal
// digit right after an escape, which gnuplot would otherwise read as part of
// it). No quote, line break, backquote (command substitution) or '@' (macro)
// from a user ever reaches the script; the value gnuplot sees is the text,
// byte for byte (bytes >= 0x80, i.e. UTF-8, are kept as they are; a NUL,
// which would end a C string, becomes '?').
std::string GnuplotString(const std::string& text) {
  std::string out = "\"";
  bool after_escape = false;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == ' ' || c == '.' || c == '_' || c == ',' || c == ':' || c == '/' ||
                      c == '(' || c == ')' || c == '=' || c == '+' || c == '-' || c >= 0x80;
    const bool octal_digit = c >= '0' && c <= '7';
    if (c == 0) {
      out += '?';
      after_escape = false;
    } else if (safe && !(after_escape && octal_digit)) {
      out += static_cast<char>(c);
      after_escape = false;
    } else {
      const char escape[5] = {'\\', static_cast<char>('0' + (c >> 6)),
                              static_cast<char>('0' + ((c >> 3) & 7)),
                              static_cast<char>('0' + (c & 7)), '\0'};
      out += escape;
      after_escape = true;
    }
  }
  return out + "\"";
}

std::string Substitute(std::string script, const std::vector<std::string>& paths) {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::string key = "{data" + std::to_string(i) + "}";
    script = ReplaceAll(std::move(script), key, GnuplotString(paths[i]));
  }
  return script;
}

std::string Header(const PlotRequest& r, const std::string& png) {
  std::ostringstream os;
  os << "set terminal pngcairo size " << r.width_px << "," << r.height_px
     << " noenhanced font 'sans,10'\n"
     << "set output " << GnuplotString(png) << "\n";
  return os.str();
}

std::string AxesScript(const Axes& axes) {
  std::ostringstream os;
  if (!axes.title.empty()) os << "set title " << GnuplotString(axes.title) << "\n";
  os << "set xlabel " << GnuplotString(axes.x_label) << "\nset ylabel "
     << GnuplotString(axes.y_label) << "\n";
  if (axes.log_y) os << "set logscale y\nset format y \"%.0e\"\n";
  os << "set grid\n";
  return os.str();
}

// A private folder (mkdtemp, mode 0700) in $TMPDIR (default /tmp) holding
// gnuplot's script, data and image under fixed names. Nobody else can create
// or plant a symlink in it; its files are created with O_EXCL | O_NOFOLLOW,
// registered for removal on SIGINT/SIGTERM/SIGHUP, and removed (with the
// folder) by the destructor.
class PrivateFolder {
 public:
  PrivateFolder() {
    const char* tmpdir = std::getenv("TMPDIR");
    const std::string base = tmpdir != nullptr && *tmpdir != '\0' ? tmpdir : "/tmp";
    std::string pattern = base + "/podid-plot-XXXXXX";
    const BlockCleanupSignals blocked;  // create and register as one step
    if (::mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("plot: cannot create a private folder in " + base + ": " +
                               std::strerror(errno));
    }
    path_ = pattern;
    folder_ = TemporaryPath(path_, TemporaryPath::Kind::kFolder);
  }
  PrivateFolder(const PrivateFolder&) = delete;
  PrivateFolder& operator=(const PrivateFolder&) = delete;
  ~PrivateFolder() {
    for (const std::string& file : files_) ::unlink(file.c_str());
    ::rmdir(path_.c_str());
  }

  const std::string& path() const { return path_; }

  /// Registers `name` (a file some program will create here); its full path.
  std::string Expect(const std::string& name) {
    files_.push_back(path_ + "/" + name);
    registrations_.emplace_back(files_.back());
    return files_.back();
  }

  /// Creates `name` (O_EXCL, O_NOFOLLOW) and fills it with `write`.
  void Write(const std::string& name, const std::function<void(std::ostream&)>& write) {
    const std::string file = Expect(name);
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) {
      throw std::runtime_error("plot: cannot create " + file + ": " + std::strerror(errno));
    }
    ::close(fd);
    std::ofstream out(file);  // the file we just created, in our private folder
    if (!out) throw std::runtime_error("plot: cannot write temporary file " + file);
    out.precision(10);
    write(out);
    out.flush();
    if (!out) throw std::runtime_error("plot: error writing temporary file " + file);
  }

 private:
  std::string path_;
  TemporaryPath folder_;
  std::vector<std::string> files_;
  std::vector<TemporaryPath> registrations_;
};

// What a gnuplot run said. Its stdout and stderr go to a file in the private
// folder, never to the user's terminal: podid relays them in its own form.
struct GnuplotRun {
  bool ok = false;
  std::string failure;             // how it failed when it printed nothing
  std::vector<std::string> lines;  // its informative lines, sanitised
};

// At most this much of gnuplot's output is read, and a relayed line keeps at
// most kGnuplotLineBytes (it may echo labels from case and data files).
constexpr std::size_t kGnuplotLogBytes = 64 * 1024;
constexpr std::size_t kGnuplotLineBytes = 200;

std::string_view Trimmed(std::string_view s) {
  const std::size_t first = s.find_first_not_of(" \t\r\f\v");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\f\v") - first + 1);
}

bool IsCaretLine(std::string_view s) {
  const std::string_view t = Trimmed(s);
  return !t.empty() && t.find_first_not_of(" \t^") == std::string_view::npos;
}

// Drops a leading `"plot.gp" line N: ` or `line N: `: where in our temporary
// script means nothing to the user.
std::string_view WithoutScriptLine(std::string_view s, const std::string& script) {
  const std::string quoted = "\"" + script + "\" ";
  if (s.substr(0, quoted.size()) == quoted) s.remove_prefix(quoted.size());
  if (s.substr(0, 5) != "line ") return s;
  std::size_t i = 5;
  while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
  if (i == 5 || s.substr(i, 2) != ": ") return s;
  return Trimmed(s.substr(i + 2));
}

// The lines of gnuplot's output worth showing: without blank lines, the
// echoed script line and the caret under it, and the script's name; control
// bytes escaped, each bounded.
std::vector<std::string> InformativeLines(const std::string& log, const std::string& script) {
  std::vector<std::string_view> raw;
  std::string_view rest(log);
  while (!rest.empty()) {
    const std::size_t end = rest.find('\n');
    raw.push_back(rest.substr(0, end));
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
  }
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (IsCaretLine(raw[i]) || (i + 1 < raw.size() && IsCaretLine(raw[i + 1]))) continue;
    const std::string_view text = WithoutScriptLine(Trimmed(raw[i]), script);
    if (text.empty()) continue;
    std::string line = Escaped(text);
    if (line.size() > kGnuplotLineBytes) {
      std::size_t cut = kGnuplotLineBytes;  // not inside a UTF-8 sequence
      while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;
      line = line.substr(0, cut) + "...";
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

// Runs `gnuplot script` in `folder` without a shell, its stdout and stderr
// into the new file `log`.
GnuplotRun RunGnuplot(const std::string& gnuplot,
                      const std::string& folder,
                      const std::string& script,
                      const std::string& log) {
  GnuplotRun run;
  // Absolute: a relative program path (PODID_GNUPLOT, a relative PATH entry)
  // would otherwise be looked up in the private folder after the chdir.
  std::error_code error;
  const std::string program = std::filesystem::absolute(gnuplot, error).string();
  if (error) {
    run.failure = error.message();
    return run;
  }
  posix_spawn_file_actions_t actions;
  if (posix_spawn_file_actions_init(&actions) != 0) {
    run.failure = "cannot prepare its start";
    return run;
  }
  // O_EXCL | O_NOFOLLOW like every file in the folder; no O_CLOEXEC, since
  // it is opened as gnuplot's own stdout.
  int code = posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                              O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0600);
  if (code == 0) code = posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  if (code == 0) code = posix_spawn_file_actions_addchdir_np(&actions, folder.c_str());
  pid_t pid = 0;
  std::vector<char*> argv = {const_cast<char*>(program.c_str()), const_cast<char*>(script.c_str()),
                             nullptr};
  if (code == 0) code = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (code != 0) {
    run.failure = std::string("cannot start it: ") + std::strerror(code);
    return run;
  }
  int status = 0;
  pid_t waited = 0;
  do {
    waited = waitpid(pid, &status, 0);
  } while (waited < 0 && errno == EINTR);
  run.ok = waited == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (waited != pid) {
    run.failure = std::string("cannot wait for it: ") + std::strerror(errno);
  } else if (WIFSIGNALED(status)) {
    run.failure = "killed by signal " + std::to_string(WTERMSIG(status));
  } else if (!run.ok) {
    run.failure = "exit status " + std::to_string(WEXITSTATUS(status));
  }
  std::ifstream in(log, std::ios::binary);
  std::string text(kGnuplotLogBytes, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  run.lines = InformativeLines(text, script);
  return run;
}

// Why gnuplot failed, for the error: its first error lines (gnuplot stops at
// the first error; warnings before it are only a fallback), else its status.
std::string FailureReason(const GnuplotRun& run) {
  const auto is_warning = [](const std::string& line) {
    return line.rfind("warning:", 0) == 0 || line.rfind("Warning:", 0) == 0;
  };
  std::vector<std::string> chosen;
  for (const bool warnings : {false, true}) {
    for (const std::string& line : run.lines) {
      if (is_warning(line) == warnings && chosen.size() < 2) chosen.push_back(line);
    }
  }
  if (chosen.empty()) return run.failure.empty() ? "no reason given" : run.failure;
  std::string reason = chosen.front();
  if (chosen.size() > 1) reason += "; " + chosen[1];
  return reason;
}

// Relays a successful run's lines (warnings such as an empty range) as notes
// naming the PNG, at most kShown of them.
void RelayGnuplotLines(const GnuplotRun& run, const std::string& png) {
  constexpr std::size_t kShown = 5;
  const std::string name = Escaped(png);
  for (std::size_t i = 0; i < run.lines.size() && i < kShown; ++i) {
    std::fprintf(stderr, "podid: note: gnuplot, %s: %s\n", name.c_str(), run.lines[i].c_str());
  }
  if (run.lines.size() > kShown) {
    std::fprintf(stderr, "podid: note: gnuplot, %s: (%zu more)\n", name.c_str(),
                 run.lines.size() - kShown);
  }
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
    // In a folder made for them (mkdtemp: new, so no existing file is
    // replaced): next to the PNG under fixed names, they overwrote the case
    // file when it was called <png>.gp.
    std::string kept = png + ".gnuplot-XXXXXX";
    if (::mkdtemp(kept.data()) == nullptr) {
      throw std::runtime_error("plot: gnuplot not found, and cannot create a folder " + kept +
                               " for the script: " + std::strerror(errno));
    }
    // Staged with the command's other files: a later failure removes them.
    if (request.batch != nullptr) request.batch->AdoptFolder(kept);
    std::vector<std::string> paths;
    for (std::size_t i = 0; i < request.data.size(); ++i) {
      paths.push_back(kept + "/data" + std::to_string(i) + ".txt");
      WriteFileAtomically(
          paths.back(),
          [&](std::ostream& os) {
            os.precision(10);
            request.data[i](os);
          },
          request.batch);
    }
    const std::string script = kept + "/plot.gp";
    WriteFileAtomically(
        script,
        [&](std::ostream& os) { os << Header(request, png) << Substitute(request.script, paths); },
        request.batch);
    std::fprintf(stderr,
                 "podid: gnuplot not found on PATH: %s not drawn; wrote %s and its data "
                 "(run 'gnuplot %s' from this folder)\n",
                 png.c_str(), script.c_str(), script.c_str());
    return PlotOutcome::kNoGnuplot;
  }

  PrivateFolder folder;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < request.data.size(); ++i) {
    names.push_back("data" + std::to_string(i));
    folder.Write(names.back(), request.data[i]);
  }
  const std::string image = folder.Expect("plot.png");
  folder.Write("plot.gp", [&](std::ostream& os) {
    os << Header(request, "plot.png") << Substitute(request.script, names) << "\nunset output\n";
  });
  const GnuplotRun run =
      RunGnuplot(gnuplot, folder.path(), "plot.gp", folder.Expect("gnuplot.log"));
  if (!run.ok) {
    throw std::runtime_error("plot: gnuplot (" + gnuplot + ") failed drawing " + png + ": " +
                             FailureReason(run));
  }
  std::error_code error;
  if (!std::filesystem::is_regular_file(image, error) ||
      std::filesystem::file_size(image, error) == 0) {
    throw std::runtime_error("plot: gnuplot wrote no image for " + png +
                             (run.lines.empty() ? "" : ": " + FailureReason(run)));
  }
  RelayGnuplotLines(run, png);
  // The user's path is written by the same safe writer as every other output.
  WriteFileAtomically(
      png,
      [&](std::ostream& os) {
        std::ifstream in(image, std::ios::binary);
        if (!in || !(os << in.rdbuf())) throw std::runtime_error("cannot copy " + image);
      },
      request.batch);
  return PlotOutcome::kWritten;
}

PlotOutcome PlotLines(const std::string& output_png,
                      const Axes& axes,
                      const std::vector<LineSeries>& series,
                      OutputBatch* batch) {
  PlotRequest r;
  r.output_png = output_png;
  r.batch = batch;
  std::ostringstream script;
  script << AxesScript(axes) << "set key outside bottom center horizontal\nplot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const LineSeries& s = series[i];
    PODID_CHECK(s.x.size() == s.y.size());
    r.data.push_back([&s](std::ostream& os) {
      for (Eigen::Index k = 0; k < s.x.size(); ++k) os << s.x(k) << ' ' << s.y(k) << '\n';
    });
    script << (i ? ", " : "") << "{data" << i << "} using 1:2 with lines lw 1.5 title "
           << GnuplotString(s.title);
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
                        const std::vector<LineSeries>& overlay,
                        OutputBatch* batch) {
  PODID_CHECK(z.rows() == x.size() && z.cols() == y.size());
  PlotRequest r;
  r.output_png = output_png;
  r.batch = batch;
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
         << "set palette rgbformulae 30,31,32\nset cblabel " << GnuplotString(z_label) << "\n"
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
           << ") with lines lw 2 lc rgb 'white' title " << GnuplotString(s.title);
  }
  script << "\n";
  r.script = script.str();
  return RenderPlot(r);
}

}  // namespace podid::cli
