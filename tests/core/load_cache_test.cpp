// LoadCache: a file or channel force interpolated once, rescaled when its gain
// or offset changes, against the interpolation of gain u + offset computed
// directly (InterpolateBandLimited is linear).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "podid/core/case_file.hpp"
#include "podid/core/interpolate.hpp"
#include "podid/core/load.hpp"
#include "podid/core/model_parameter.hpp"
#include "podid/core/simulate.hpp"
#include "podid/core/simulator.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::TempDir;

// A 1-dof oscillator driven by a file force at 4 sub-steps; the file covers
// t = 0.02-0.07 s of the 0.1 s record, so the force is 0 outside it (1_in).
constexpr const char* kCase = R"([model]
type = "matrices"
mass = "m.mtx"
stiffness = "k.mtx"
[damping]
type = "rayleigh"
alpha = 5.0
[[nonlinearity]]
type = "cubic"
dof = 1
k3 = 1.0e6
[force]
type = "file"
dof = 1
file = "f.csv"
column = "volts"
gain = 3.0
offset = 0.5
[time]
duration = 0.1
step = 1.0e-3
[integrator]
substeps = 4
[sensors]
dofs = [1]
)";

std::string ForceCsv() {
  std::string text = "t,volts\n";
  for (int i = 0; i <= 50; ++i) {
    const double t = 0.02 + i * 1e-3;
    text += std::to_string(t) + "," + std::to_string(std::sin(2 * 3.141592653589793 * 60 * t)) + "\n";
  }
  return text;
}

struct Fixture {
  TempDir dir;
  std::string path;
  Fixture() {
    dir.Write("m.mtx", "%%MatrixMarket matrix coordinate real symmetric\n1 1 1\n1 1 1.0\n");
    dir.Write("k.mtx", "%%MatrixMarket matrix coordinate real symmetric\n1 1 1\n1 1 1.0e5\n");
    dir.Write("f.csv", ForceCsv());
    path = dir.Write("case.toml", kCase);
  }
};

// gain u 1_in + offset 1_in on the data's grid (the file's samples fall on it),
// interpolated directly: the reference the cache's rescaling must reproduce.
Eigen::VectorXd Direct(const CaseSpec& spec, double gain, double offset) {
  const int samples = spec.time.samples();
  Eigen::VectorXd coarse = Eigen::VectorXd::Zero(samples);
  const Eigen::VectorXd& ft = spec.force.history_N.file_time_s;
  const Eigen::VectorXd& fv = spec.force.history_N.file_values;
  for (int i = 0; i < samples; ++i) {
    const double t = i * spec.time.step_s;
    for (Eigen::Index j = 0; j < ft.size(); ++j) {
      if (std::abs(ft[j] - t) < 1e-9) coarse[i] = gain * fv[j] + offset;
    }
  }
  return InterpolateBandLimited(coarse, spec.integrator.substeps);
}

// The interpolation is linear; rescaling the two cached parts instead of
// interpolating their combination changes rounding only: 1e-12 of the force's
// peak (the FFT's round-off is ~1e-15 of it per bin).
constexpr double kLinearity = 1e-12;

TEST(LoadCacheTest, GainAndOffsetRescaleTheCachedInterpolation) {
  const Fixture f;
  CaseSpec spec = CaseDocument::Load(f.path).ToSpec();
  const BeamModel model = BeamModel::Build(spec);
  LoadCache cache;
  const ExternalLoad first = BuildLoad(spec, model, &cache);
  EXPECT_EQ(cache.misses(), 1);
  const Eigen::VectorXd direct = Direct(spec, 3.0, 0.5);
  ASSERT_EQ(first.history.cols(), direct.size());
  const double peak = direct.cwiseAbs().maxCoeff();
  ASSERT_GT(peak, 1.0);
  EXPECT_LE((first.history.row(0).transpose() - direct).cwiseAbs().maxCoeff(), kLinearity * peak);
  // Outside the file the force is 0, not the offset: the offset follows 1_in.
  EXPECT_LT(std::abs(first.history(0, 0)), kLinearity * peak);

  spec.force.history_N.gain = -7.0;
  spec.force.history_N.offset = 2.0;
  const ExternalLoad second = BuildLoad(spec, model, &cache);
  EXPECT_EQ(cache.misses(), 1);  // rescaled, not interpolated again
  EXPECT_LE((second.history.row(0).transpose() - Direct(spec, -7.0, 2.0)).cwiseAbs().maxCoeff(),
            kLinearity * 7.0 * peak);
  // Without a cache: the same values to the bit (one formula).
  EXPECT_TRUE((BuildLoad(spec, model).history.array() == second.history.array()).all());

  spec.force.history_N.file_values[10] += 1.0;  // another column: interpolated again
  BuildLoad(spec, model, &cache);
  EXPECT_EQ(cache.misses(), 2);
  spec.integrator.substeps = 2;  // another grid too
  BuildLoad(spec, model, &cache);
  EXPECT_EQ(cache.misses(), 3);
}

TEST(LoadCacheTest, SimulatorGainChangeEqualsAFreshSimulation) {
  const Fixture f;
  const CaseDocument document = CaseDocument::Load(f.path);
  Simulator simulator(document.ToSpec());
  simulator.Run();
  const ModelParameter gain = ModelParameter::Resolve(document.ToSpec(), "force.gain");
  std::string why;
  ASSERT_TRUE(simulator.Set(gain, 4.5, &why)) << why;
  const SimulationResult cached = simulator.Run();
  EXPECT_EQ(simulator.load_cache().misses(), 1);  // the gain rescaled the first interpolation
  CaseDocument changed = document;
  changed.SetNumber("force.gain", 4.5);
  const SimulationResult fresh = Simulate(changed.ToSpec(), SimulateOptions{false});
  ASSERT_TRUE(cached.summary.IsSolutionUsable()) << cached.summary.message;
  // The same load to the bit (LoadCacheTest above), hence the same response.
  EXPECT_TRUE((cached.sensors.values.array() == fresh.sensors.values.array()).all());
  EXPECT_GT(cached.sensors.values.cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace podid
