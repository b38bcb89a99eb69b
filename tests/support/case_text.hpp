#pragma once
// The reference case (examples/beam.toml) as TOML text, one table at a time,
// for tests that write their own case: a test joins the tables it keeps and
// writes out only what it changes. Each table ends with a newline.

#include <string>

namespace podid::testing {

/// [beam]: the reference steel beam, 6 elements of a square section.
inline std::string BeamTable() {
  return "[beam]\n"
         "length = 0.593\n"
         "elements = 6\n"
         "youngs_modulus = 2.05e11\n"
         "density = 7800.0\n"
         "area = 0.196e-3\n";
}

/// [damping]: Rayleigh damping from the modal ratios of modes 1 and 2.
inline std::string RayleighTable(const std::string& modal_ratios = "[0.01, 0.01]") {
  return "[damping]\ntype = \"rayleigh\"\nmodal_ratios = " + modal_ratios + "\n";
}

/// [[nonlinearity]]: the cubic spring at the free end (node 6).
inline std::string CubicTable(const std::string& k3 = "5.0e9") {
  return "[[nonlinearity]]\ntype = \"cubic\"\nnode = 6\nk3 = " + k3 + "\n";
}

/// [initial]: released from the static deflection under a tip force.
inline std::string InitialTable() { return "[initial]\nstatic_tip_force = 20.0\n"; }

/// [time]: steps of 0.2 ms.
inline std::string TimeTable(const std::string& duration = "0.1") {
  return "[time]\nduration = " + duration + "\nstep = 2.0e-4\n";
}

/// [sensors]: the transverse displacement of every node.
inline std::string SensorsTable() { return "[sensors]\ndof = \"w\"\n"; }

/// [noise]: none.
inline std::string NoiseTable() { return "[noise]\nrelative = 0.0\nseed = 1\n"; }

/// [[identify.parameter]]: k3 in units of 1e8 N/m^3.
inline std::string IdentifyK3Table() {
  return "[[identify.parameter]]\n"
         "name = \"knl\"\n"
         "key = \"nonlinearity.0.k3\"\n"
         "scale = 1.0e8\n"
         "start = 40.0\n"
         "lower = 0.0\n"
         "upper = 200.0\n";
}

}  // namespace podid::testing
