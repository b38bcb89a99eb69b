// Tests of podid/wavelet/plans.hpp: the on-disk FFTW wisdom cache.
// Every test in this binary runs with XDG_CACHE_HOME pointing at a private
// temporary folder (set below, before main), so none reads or writes the
// user's real cache.
#include "podid/wavelet/plans.hpp"

#include <fftw3.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../../wavelet/src/wisdom_file.hpp"  // internal: the cache file's reader
#include "test_support.hpp"

namespace podid::wavelet {
namespace {

namespace fs = std::filesystem;

// The private cache root, made before any test runs.
const std::string& CacheRoot() {
  static const std::string root = [] {
    std::string pattern = fs::temp_directory_path().string() + "/podid-wavelet-test-XXXXXX";
    const char* made = ::mkdtemp(pattern.data());
    if (made == nullptr) std::abort();
    ::setenv("XDG_CACHE_HOME", made, 1);
    return std::string(made);
  }();
  return root;
}
const bool kCacheRedirected = !CacheRoot().empty();
// Removes the private cache root when the test binary exits.
struct RemoveRoot {
  ~RemoveRoot() {
    std::error_code ec;
    fs::remove_all(CacheRoot(), ec);
  }
} remove_root;

struct ScopedCache {
  explicit ScopedCache(const std::string& name) : folder(CacheRoot() + "/" + name) {
    fs::create_directories(folder);
    ::setenv("XDG_CACHE_HOME", folder.c_str(), 1);
  }
  ~ScopedCache() { ::setenv("XDG_CACHE_HOME", CacheRoot().c_str(), 1); }
  std::string folder;
};

TEST(FftWisdom, PathFollowsXdgThenHome) {
  ASSERT_TRUE(kCacheRedirected);
  ScopedCache cache("path");
  EXPECT_EQ(FftWisdomPath(), cache.folder + "/podid/fftw3-wisdom");
  ::setenv("XDG_CACHE_HOME", "relative/dir", 1);  // not absolute: ignored (XDG spec)
  const char* home = std::getenv("HOME");
  if (home != nullptr && home[0] != '\0') {
    EXPECT_EQ(FftWisdomPath(), std::string(home) + "/.cache/podid/fftw3-wisdom");
  }
}

TEST(FftWisdom, MeasuringSavesWisdomOnceAndItIsReused) {
  ScopedCache cache("measure");
  // Lengths no other test plans, one of each kind (the complex forward 1176
  // is a different plan from the real forward of the same length).
  const FftLengths lengths{{1176}, {1350}, {{49, 6}}, {1176}};
  const PlanSummary first = MeasureFftPlans(lengths);
  EXPECT_EQ(first.measured, 4);
  EXPECT_EQ(first.known, 0);
  EXPECT_TRUE(first.saved) << first.message;
  EXPECT_EQ(first.wisdom_path, cache.folder + "/podid/fftw3-wisdom");
  ASSERT_TRUE(fs::exists(first.wisdom_path));
  EXPECT_GT(fs::file_size(first.wisdom_path), 0u);
  EXPECT_EQ(fs::status(cache.folder + "/podid").permissions() & fs::perms::all,
            fs::perms::owner_all);
  EXPECT_EQ(fftw_import_wisdom_from_filename(first.wisdom_path.c_str()), 1);
  const PlanSummary second = MeasureFftPlans(lengths);
  EXPECT_EQ(second.measured, 0);
  EXPECT_EQ(second.known, 4);
  EXPECT_FALSE(second.saved);  // nothing new to write
}

TEST(FftWisdom, PatientEffortMeasuresAgainAndServesMeasureRequests) {
  // FFTW_MEASURE wisdom does not satisfy FFTW_PATIENT (FFTW_WISDOM_ONLY finds
  // no plan), so a patient request measures again; patient wisdom then
  // serves both efforts and is in the cache file.
  ScopedCache cache("patient");
  const FftLengths lengths{{150}, {126}, {{21, 4}}, {150}};  // no other test measures these
  const PlanSummary measure = MeasureFftPlans(lengths, PlanEffort::kMeasure);
  EXPECT_EQ(measure.measured, 4);
  const PlanSummary patient = MeasureFftPlans(lengths, PlanEffort::kPatient);
  EXPECT_EQ(patient.measured, 4);
  EXPECT_EQ(patient.known, 0);
  EXPECT_TRUE(patient.saved) << patient.message;
  const PlanSummary again = MeasureFftPlans(lengths, PlanEffort::kPatient);
  EXPECT_EQ(again.measured, 0);
  EXPECT_EQ(again.known, 4);
  EXPECT_EQ(MeasureFftPlans(lengths, PlanEffort::kMeasure).known, 4);
  // The cache file holds patient wisdom: in a child (so that this process's
  // wisdom stays), FFTW with only the file's wisdom finds the in-place
  // backward plan of 126 points at FFTW_PATIENT | FFTW_WISDOM_ONLY.
  const std::string path = patient.wisdom_path;
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    fftw_forget_wisdom();
    if (fftw_import_wisdom_from_filename(path.c_str()) != 1) ::_exit(2);
    fftw_complex* data = fftw_alloc_complex(126);
    fftw_plan plan =
        fftw_plan_dft_1d(126, data, data, FFTW_BACKWARD, FFTW_PATIENT | FFTW_WISDOM_ONLY);
    ::_exit(plan != nullptr ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

TEST(FftWisdom, EstimatedPlansWriteNothing) {
  // kEstimate (the default) never measures and never writes the cache;
  // kMeasure measures what the cache lacks and stores it.
  ScopedCache cache("estimate");
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(177, 0.0, 1.0).array().sin();
  CwtOptions options;
  options.frequencies.min_frequency_Hz = 100.0;
  options.frequencies.max_frequency_Hz = 400.0;
  Cwt(x, 1e-3, options);
  EXPECT_FALSE(fs::exists(cache.folder + "/podid"));
  options.planning = FftPlanning::kMeasure;
  Cwt(x, 1e-3, options);
  EXPECT_TRUE(fs::exists(cache.folder + "/podid/fftw3-wisdom"));
}

TEST(FftWisdom, ConcurrentProcessesLeaveAReadableFileAndNoTemporaries) {
  // Four processes measure different lengths and save at once: each writes
  // a unique temporary file and renames it, so the file is always complete.
  ScopedCache cache("concurrent");
  std::vector<pid_t> children;
  for (int c = 0; c < 4; ++c) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      const PlanSummary s = MeasureFftPlans({{202 + 2 * c}, {333 + 3 * c}, {}, {}});
      if (!(s.saved && s.measured == 2))
        std::fprintf(stderr, "child %d: measured %d known %d saved %d %s\n", c, s.measured, s.known,
                     s.saved, s.message.c_str());
      ::_exit(s.saved && s.measured == 2 ? 0 : 1);
    }
    children.push_back(pid);
  }
  for (pid_t pid : children) {
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  const std::string path = cache.folder + "/podid/fftw3-wisdom";
  EXPECT_EQ(fftw_import_wisdom_from_filename(path.c_str()), 1);
  for (const auto& entry : fs::directory_iterator(cache.folder + "/podid")) {
    EXPECT_EQ(entry.path().filename(), "fftw3-wisdom") << "left behind: " << entry.path();
  }
}

TEST(FftWisdom, AnUnwritableCacheIsReportedNotFatal) {
  ScopedCache cache("unwritable");
  const std::string blocker = cache.folder + "/file";
  std::ofstream(blocker) << "not a folder\n";
  ::setenv("XDG_CACHE_HOME", blocker.c_str(), 1);  // .../file/podid cannot be made
  PlanSummary s;
  ASSERT_NO_THROW(s = MeasureFftPlans({{1456}, {}, {}, {}}));
  EXPECT_EQ(s.measured, 1);
  EXPECT_FALSE(s.saved);
  EXPECT_NE(s.message.find("cannot create " + blocker + "/podid"), std::string::npos) << s.message;
  // A garbage cache file is ignored (estimated plans), never an error.
  ScopedCache garbage("garbage");
  fs::create_directories(garbage.folder + "/podid");
  std::ofstream(garbage.folder + "/podid/fftw3-wisdom") << "(fftw-3.3.10 fftw_wisdom\n(garbage";
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(901, 0.0, 1.0).array().cos();
  EXPECT_NO_THROW(Cwt(x, 1e-3));
}

// The first line FFTW exports for this build: "(fftw-3.3.10 fftw_wisdom" and
// the four words of its configuration's signature.
std::string WisdomHeader() {
  char* text = fftw_export_wisdom_to_string();
  const std::string all(text);
  fftw_free(text);
  return all.substr(0, all.find('\n'));
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(FftWisdom, CheckAcceptsWhatFftwExportsAndNamesWhatIsWrong) {
  ScopedCache cache("shape");
  const PlanSummary s = MeasureFftPlans({{1134}, {}, {}, {}});  // no other test plans 1134
  ASSERT_TRUE(s.saved) << s.message;
  EXPECT_EQ(internal::CheckWisdomText(ReadAll(s.wisdom_path)), "");
  char* text = fftw_export_wisdom_to_string();
  EXPECT_EQ(internal::CheckWisdomText(text), "");
  fftw_free(text);
  const std::string h = WisdomHeader() + "\n";
  const std::string sig = " #x9bc27a57 #x27daf66a #x4b7172f2 #xbbaff3a8)\n";
  const std::string entry = "  (fftw_dft_nop_register 0 #x11bdd #x11bdd #x0" + sig;
  struct Case {
    std::string text, why;
  };
  const std::vector<Case> cases = {
      {h + entry + ")\n", ""},
      {h + ")", ""},
      {"", "line 1: expected '('"},
      {"(fftw-3.3.10 fftw_wisdom #x1 #x2 #x3\n)\n", "line 2: expected \"#x\""},
      // The fields FFTW's importer CK()s (abort) when they overflow flags_t.
      {h + "  (fftw_dft_nop_register 0 #xffffffff #x11bdd #x0" + sig + ")\n",
       "line 2: expected flags l below #x100000"},
      {h + "  (fftw_dft_nop_register 0 #x11bdd #x100000 #x0" + sig + ")\n",
       "line 2: expected flags u below #x100000"},
      {h + "  (TIMEOUT 0 #x0 #x0 #x200" + sig + ")\n", "line 2: expected timelimit below #x200"},
      {h + "  (" + std::string(64, 'a') + " 0 #x0 #x0 #x0" + sig + ")\n",
       "line 2: expected a name of 1-63 letters, digits or '_'"},
      {h + "  (fftw_dft_nop_register 1234567890 #x0 #x0 #x0" + sig + ")\n",
       "line 2: expected 1-9 digits"},
      {h + "  (fftw_dft_nop_register 0 #x0 #x0 #x0 #x123456789 #x0 #x0 #x0)\n)\n",
       "line 2: expected 1-8 hex digits"},
      {h + "  (fftw_dft_nop_register 0 #x0 #x0 #x0" + sig,
       "line 3: expected '(' (an entry) or ')' (the end)"},
      {h + entry + ")\n(fftw", "line 4: expected the end after the closing ')'"},
      {h + std::string("  (fftw_dft\0nop 0 #x0 #x0 #x0", 29) + sig + ")\n",
       "line 2: expected a blank"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(internal::CheckWisdomText(c.text), c.why) << c.text;
  }
}

// A cache file podid cannot trust is ignored (estimated plans), said so in
// the plan summary, and replaced by the next measurement; never a hang or an
// abort. Before podid read the file itself, FFTW's reader blocked for ever on
// the FIFO and on /dev/zero and aborted the process on the overflowing entry.
TEST(FftWisdom, HostileCacheFilesAreIgnoredAndReplaced) {
  struct Case {
    std::string name, why;
    int length;  // a real forward length no other test measures
  };
  const std::vector<Case> cases = {
      {"fifo", "not a regular file", 1152},
      {"zero", "not a regular file", 1200},
      {"overflow", "line 2: expected flags l below #x100000", 1215},
      {"huge", "expected at most 16777216 bytes, got 16777217", 1225},
  };
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(901, 0.0, 1.0).array().cos();
  const std::string header = WisdomHeader();
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ScopedCache cache("hostile-" + c.name);
    fs::create_directories(cache.folder + "/podid");
    const std::string path = cache.folder + "/podid/fftw3-wisdom";
    if (c.name == "fifo") {
      ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
    } else if (c.name == "zero") {
      fs::create_symlink("/dev/zero", path);
    } else if (c.name == "overflow") {
      std::ofstream(path) << header << "\n  (fftw_dft_nop_register 0 #xffffffff #x11bdd #x0 "
                          << "#x9bc27a57 #x27daf66a #x4b7172f2 #xbbaff3a8)\n)\n";
    } else {
      std::ofstream(path) << header << "\n)\n";
      fs::resize_file(path, internal::kMaxWisdomBytes + 1);  // sparse: no 16 MiB written
    }
    EXPECT_NO_THROW(Cwt(x, 1e-3));
    const PlanSummary s = MeasureFftPlans({{c.length}, {}, {}, {}});
    EXPECT_EQ(s.ignored, path + ": " + c.why);
    EXPECT_EQ(s.measured, 1);
    ASSERT_TRUE(s.saved) << s.message;
    ASSERT_TRUE(fs::is_regular_file(fs::symlink_status(path)));
    EXPECT_EQ(internal::CheckWisdomText(ReadAll(path)), "");
  }
}

TEST(FftWisdom, BadLengthsAreRejectedBeforeMeasuring) {
  ScopedCache cache("bad");
  PODID_EXPECT_THROW_WITH(MeasureFftPlans({{1024, 0}, {}, {}, {}}), std::invalid_argument,
                          "FFT length: expected 1..134217728, got 0");
  EXPECT_FALSE(fs::exists(cache.folder + "/podid"));
}

TEST(FftLengthsMerge, EachListSortedWithEachLengthOnce) {
  FftLengths lengths{{9216}, {9216, 576}, {{144, 64}, {288, 32}}, {9216}};
  MergeFftLengths({{10240, 9216}, {640, 10240, 576}, {{160, 64}, {144, 64}}, {10240}}, &lengths);
  EXPECT_EQ(lengths.real_forward, (std::vector<int>{9216, 10240}));
  EXPECT_EQ(lengths.complex_backward, (std::vector<int>{576, 640, 9216, 10240}));
  EXPECT_EQ(lengths.interleaved_backward,
            (std::vector<std::pair<int, int>>{{144, 64}, {160, 64}, {288, 32}}));
  EXPECT_EQ(lengths.complex_forward, (std::vector<int>{9216, 10240}));
  // Merging into an empty set, and merging nothing, keep the rule.
  FftLengths empty;
  MergeFftLengths(lengths, &empty);
  MergeFftLengths({}, &empty);
  EXPECT_EQ(empty.complex_backward, lengths.complex_backward);
  EXPECT_EQ(empty.interleaved_backward, lengths.interleaved_backward);
}

}  // namespace
}  // namespace podid::wavelet
