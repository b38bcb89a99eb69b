// podid as a library: simulate the reference beam, decompose it, and evaluate
// the paper's objective against the measured record.
// Usage: podid_consumer examples/beam.toml examples/measured_knl50_T0.1.csv
#include <cstdio>

#include "podid/core/case_file.hpp"
#include "podid/core/io.hpp"
#include "podid/core/simulate.hpp"
#include "podid/ident/objective.hpp"
#include "podid/pod/pod.hpp"

int main(int argc, char** argv) {
  if (argc != 3) return std::fprintf(stderr, "usage: %s CASE.toml MEASURED.csv\n", argv[0]), 1;
  const podid::CaseDocument doc = podid::CaseDocument::Load(argv[1]);
  const podid::SimulationResult sim = podid::Simulate(doc.ToSpec());
  const podid::PodResult pod = podid::ComputePod(sim.sensors);  // X = sensors x samples (eq. 17)
  std::printf("%s\nPOM 1 holds %.2f %% of the energy\n", sim.summary.BriefReport().c_str(),
              100 * pod.energy_fraction[0]);

  const podid::TimeSeries measured = podid::ReadCsv(argv[2]);
  const podid::ident::ObjectiveOptions options;  // one weighting: "full", eq. 19: dU + dS + dV
  const podid::ident::ObjectiveFunction objective(doc, measured, options);
  podid::ident::EvaluationWorkspace workspace;  // the cached simulation, reused
  for (double knl : {40.0, 50.0}) {
    const double f = objective.Evaluate(Eigen::VectorXd::Constant(1, knl), &workspace).values[0];
    std::printf("F(knl = %g) = %.4g\n", knl, f);
  }
  return sim.summary.IsSolutionUsable() ? 0 : 2;
}
