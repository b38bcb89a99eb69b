// The model tables of a case file: [model], [beam] (ends, segments), [[mass]],
// [[spring]], [damping], [[nonlinearity]], [initial] and [sensors]
// (docs/case-file.md). The schema rows are in case_file.cpp.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "case_internal.hpp"
#include "podid/core/model_io.hpp"

namespace podid::case_detail {
namespace {

/// Largest number of [[mass]], [[spring]] or [[nonlinearity]] tables.
constexpr std::size_t kMaxItems = 100000;

BeamEnd ReadEnd(const Section& s, std::string_view name, std::string_view fallback) {
  const std::string v = s.Choice(name, {"clamped", "pinned", "free"}, fallback);
  return v == "clamped" ? BeamEnd::kClamped : (v == "pinned" ? BeamEnd::kPinned : BeamEnd::kFree);
}

/// A cross-section: `area` (square), `width` + `height`, or `area` +
/// `second_moment`. Returns false when the table gives none of them.
bool ReadCrossSection(const Section& s, const std::string& prefix, double* area_m2,
                      double* second_moment_m4) {
  const auto area = s.OptionalReal("area", Positive("m^2"));
  const auto width = s.OptionalReal("width", Positive("m"));
  const auto height = s.OptionalReal("height", Positive("m"));
  const auto moment = s.OptionalReal("second_moment", Positive("m^4"));
  if (area) {
    if (width || height) {
      s.Fail(width ? "width" : "height",
             "either " + prefix + "area (square section) or " + prefix + "width and " + prefix +
                 "height",
             "both");
    }
    *area_m2 = *area;
    *second_moment_m4 = moment ? *moment : *area * *area / 12.0;  // square: side^4 / 12
    return true;
  }
  if (moment) {
    s.Fail("second_moment", prefix + "second_moment only together with " + prefix + "area",
           "no " + prefix + "area");
  }
  if (width && height) {
    *area_m2 = *width * *height;
    *second_moment_m4 = *width * std::pow(*height, 3) / 12.0;
    return true;
  }
  if (width || height) {
    s.FailSection(prefix + "area (square section) or " + prefix + "width and " + prefix + "height",
                  width ? "only " + prefix + "width" : "only " + prefix + "height");
  }
  return false;
}

BeamSpec ReadBeam(const CaseDocument::Impl& doc) {
  const Section s = SubSection(doc, "beam", true);
  BeamSpec beam;
  beam.left = ReadEnd(s, "left", "clamped");
  beam.right = ReadEnd(s, "right", "free");
  const toml::node* segments = s.Node("segment");
  if (segments == nullptr) {
    beam.length_m = s.Real("length", Positive("m"));
    beam.elements = static_cast<int>(s.Integer("elements", {1, kMaxElements}));
    beam.youngs_modulus_Pa = s.Real("youngs_modulus", Positive("Pa"));
    beam.density_kg_per_m3 = s.Real("density", Positive("kg/m^3"));
    if (!ReadCrossSection(s, "beam.", &beam.area_m2, &beam.second_moment_m4)) {
      s.FailSection("beam.area (square section) or beam.width and beam.height", "neither");
    }
  } else {
    for (const char* key : {"length", "elements"}) {
      if (s.Has(key)) {
        s.Fail(key, std::string("no beam.") + key + " with [[beam.segment]] (each segment has its own)",
               Describe(s.Node(key)));
      }
    }
    // [beam]'s material and section are the segments' defaults.
    const bool has_section = ReadCrossSection(s, "beam.", &beam.area_m2, &beam.second_moment_m4);
    const auto e = s.OptionalReal("youngs_modulus", Positive("Pa"));
    const auto rho = s.OptionalReal("density", Positive("kg/m^3"));
    const auto& array = *segments->as_array();  // shape checked by CheckKnown
    long long total = 0;
    for (std::size_t i = 0; i < array.size(); ++i) {
      const std::string key = "beam.segment." + std::to_string(i);
      const Section g(doc, array.get(i)->as_table(), key);
      BeamSegmentSpec seg;
      seg.length_m = g.Real("length", Positive("m"));
      seg.elements = static_cast<int>(g.Integer("elements", {1, kMaxElements}));
      total += seg.elements;
      if (total > kMaxElements) {
        g.Fail("elements", "at most " + std::to_string(kMaxElements) + " elements over all segments",
               std::to_string(total));
      }
      const auto ge = g.OptionalReal("youngs_modulus", Positive("Pa"));
      const auto grho = g.OptionalReal("density", Positive("kg/m^3"));
      if (!ge && !e) g.Fail("youngs_modulus", "a modulus here or in [beam] (Pa)", "neither");
      if (!grho && !rho) g.Fail("density", "a density here or in [beam] (kg/m^3)", "neither");
      seg.youngs_modulus_Pa = ge ? *ge : *e;
      seg.density_kg_per_m3 = grho ? *grho : *rho;
      if (!ReadCrossSection(g, key + ".", &seg.area_m2, &seg.second_moment_m4)) {
        if (!has_section) {
          g.FailSection(key + ".area (square), width and height, or area and second_moment, here "
                        "or in [beam]",
                        "neither");
        }
        seg.area_m2 = beam.area_m2;
        seg.second_moment_m4 = beam.second_moment_m4;
      }
      beam.segments.push_back(seg);
      beam.length_m += seg.length_m;
    }
    if (beam.segments.empty()) s.Fail("segment", "at least one [[beam.segment]]", "none");
    beam.elements = static_cast<int>(total);
    const BeamSegmentSpec& first = beam.segments.front();
    beam.youngs_modulus_Pa = first.youngs_modulus_Pa;
    beam.density_kg_per_m3 = first.density_kg_per_m3;
    beam.area_m2 = first.area_m2;
    beam.second_moment_m4 = first.second_moment_m4;
  }
  return beam;
}

/// The tables of an array of tables `name` (empty when absent), bounded.
std::vector<Section> Tables(const CaseDocument::Impl& doc, std::string_view name) {
  std::vector<Section> out;
  const toml::node* node = doc.root.get(name);
  if (node == nullptr) return out;
  const auto& array = *node->as_array();  // shape checked by CheckKnown
  if (array.size() > kMaxItems) {
    doc.Fail(name, "at most " + std::to_string(kMaxItems) + " [[" + std::string(name) + "]] tables",
             std::to_string(array.size()));
  }
  for (std::size_t i = 0; i < array.size(); ++i) {
    out.emplace_back(doc, array.get(i)->as_table(), std::string(name) + "." + std::to_string(i));
  }
  return out;
}

int LowestNode(const BeamSpec& beam) { return beam.left == BeamEnd::kClamped ? 1 : 0; }

DampingSpec ReadDamping(const CaseDocument::Impl& doc, int dofs) {
  const Section s = SubSection(doc, "damping", false);
  DampingSpec damping;
  if (!s.present()) return damping;
  const std::string type = s.Choice("type", {"rayleigh", "none"});
  if (type == "none") {
    // The other keys are ignored, so that `--set damping.type=none` works.
    damping.type = DampingType::kNone;
    return damping;
  }
  damping.type = DampingType::kRayleigh;
  s.OnlyKeys({"type", "modal_ratios", "modes", "alpha", "beta"}, "for type \"rayleigh\"");
  if (s.Has("modal_ratios")) {
    if (s.Has("alpha") || s.Has("beta")) {
      s.Fail(s.Has("alpha") ? "alpha" : "beta", "either damping.modal_ratios or damping.alpha/beta",
             "both");
    }
    damping.from_modal_ratios = true;
    const auto ratios = s.RealArray("modal_ratios", 2, {0.0, false, 1.0, true, ""});
    damping.modal_ratios = {ratios[0], ratios[1]};
    if (s.Has("modes")) {
      const auto modes = s.IntegerArray("modes", 2, {1, dofs});
      if (modes[0] == modes[1]) {
        s.Fail("modes", "two different mode numbers",
               "[" + std::to_string(modes[0]) + ", " + std::to_string(modes[1]) + "]");
      }
      damping.modes = {static_cast<int>(modes[0]), static_cast<int>(modes[1])};
    }
  } else if (s.Has("alpha") || s.Has("beta")) {
    if (s.Has("modes")) s.Fail("modes", "damping.modes only with damping.modal_ratios", "modes");
    damping.alpha_per_s = s.Real("alpha", NonNegative("1/s"), 0.0);
    damping.beta_s = s.Real("beta", NonNegative("s"), 0.0);
  } else {
    s.FailSection("damping.modal_ratios = [z1, z2] or damping.alpha/beta for type \"rayleigh\"",
                  "neither");
  }
  return damping;
}

std::vector<NonlinearitySpec> ReadNonlinearities(const CaseDocument::Impl& doc, const CaseSpec& spec) {
  std::vector<NonlinearitySpec> out;
  const bool beam = spec.model.type == ModelType::kBeam;
  const int n = spec.dofs();
  for (const Section& s : Tables(doc, "nonlinearity")) {
    NonlinearitySpec nl;
    const std::string type = s.Choice("type", {"cubic", "polynomial", "gap", "friction"});
    const int given = int{s.Has("node")} + int{s.Has("nodes")} + int{s.Has("dof")} + int{s.Has("dofs")};
    if (given > 1) s.FailSection("one of node, nodes, dof, dofs", std::to_string(given) + " of them");
    if (s.Has("dof")) {
      nl.dof = static_cast<int>(s.Integer("dof", {1, n}));
    } else if (s.Has("dofs")) {
      const auto d = s.IntegerArray("dofs", 2, {1, n});
      if (d[0] == d[1]) s.Fail("dofs", "two different dofs", "dof " + std::to_string(d[0]) + " twice");
      nl.dof = static_cast<int>(d[0]);
      nl.dof2 = static_cast<int>(d[1]);
    } else if (!beam) {
      s.FailSection("dof = i or dofs = [i, j] (model dofs 1.." + std::to_string(n) +
                        ") for imported matrices",
                    given ? "a node" : "neither");
    } else if (s.Has("nodes")) {
      const auto d = s.IntegerArray("nodes", 2, {0, spec.beam.elements});
      if (d[0] == d[1]) s.Fail("nodes", "two different nodes", "node " + std::to_string(d[0]) + " twice");
      nl.node = static_cast<int>(d[0]);
      nl.node2 = static_cast<int>(d[1]);
    } else {
      nl.node = static_cast<int>(s.OptionalInteger("node", {LowestNode(spec.beam), spec.beam.elements})
                                     .value_or(spec.beam.elements));
    }
    const std::string why = "for type \"" + type + "\"";
    if (type == "cubic") {
      s.OnlyKeys({"type", "node", "nodes", "dof", "dofs", "k3"}, why);
      nl.type = NonlinearType::kCubic;
      nl.k3_N_per_m3 = s.Real("k3", AnyReal("N/m^3"));
    } else if (type == "polynomial") {
      s.OnlyKeys({"type", "node", "nodes", "dof", "dofs", "k1", "k2", "k3"}, why);
      nl.type = NonlinearType::kPolynomial;
      nl.k1_N_per_m = s.Real("k1", AnyReal("N/m"), 0.0);
      nl.k2_N_per_m2 = s.Real("k2", AnyReal("N/m^2"), 0.0);
      nl.k3_N_per_m3 = s.Real("k3", AnyReal("N/m^3"), 0.0);
    } else if (type == "gap") {
      s.OnlyKeys({"type", "node", "nodes", "dof", "dofs", "gap", "stiffness"}, why);
      nl.type = NonlinearType::kGap;
      nl.gap_m = s.Real("gap", NonNegative("m"));
      nl.contact_stiffness_N_per_m = s.Real("stiffness", Positive("N/m"));
    } else {
      s.OnlyKeys({"type", "node", "nodes", "dof", "dofs", "mu", "normal_force", "velocity_scale"}, why);
      nl.type = NonlinearType::kFriction;
      nl.friction_coefficient = s.Real("mu", NonNegative(""));
      nl.normal_force_N = s.Real("normal_force", NonNegative("N"));
      nl.regularisation_velocity_m_per_s = s.Real("velocity_scale", Positive("m/s"));
    }
    out.push_back(nl);
  }
  return out;
}

InitialSpec ReadInitial(const CaseDocument::Impl& doc, const CaseSpec& spec) {
  const Section s = SubSection(doc, "initial", false);
  InitialSpec initial;
  const int dofs = spec.dofs();
  const bool tip = s.Has("static_tip_force"), any_force = tip || s.Has("static_force");
  if (tip && s.Has("static_force")) {
    s.Fail("static_force", "either initial.static_force or initial.static_tip_force (the same)",
           "both");
  }
  if (any_force) {
    const char* force_key = tip ? "static_tip_force" : "static_force";
    if (s.Has("displacement") || s.Has("velocity")) {
      s.Fail(s.Has("displacement") ? "displacement" : "velocity",
             std::string("either initial.") + force_key + " or initial.displacement/velocity", "both");
    }
    initial.type = InitialType::kStaticForce;
    initial.static_force_N = s.Real(force_key, AnyReal("N"));
    ReadNodeOrDof(s, spec, &initial.static_force_node, &initial.static_force_dof);
  } else if (s.Has("displacement") || s.Has("velocity")) {
    for (const char* key : {"node", "dof"}) {
      if (s.Has(key)) {
        s.Fail(key, std::string("initial.") + key + " only with initial.static_tip_force (or static_force)",
               Describe(s.Node(key)));
      }
    }
    initial.type = InitialType::kExplicit;
    initial.displacement = Eigen::VectorXd::Zero(dofs);
    initial.velocity = Eigen::VectorXd::Zero(dofs);
    const auto n = static_cast<std::size_t>(dofs);
    if (s.Has("displacement")) {
      const auto x = s.RealArray("displacement", n, AnyReal("m and rad, one per model dof"));
      initial.displacement = Eigen::Map<const Eigen::VectorXd>(x.data(), dofs);
    }
    if (s.Has("velocity")) {
      const auto v = s.RealArray("velocity", n, AnyReal("m/s and rad/s, one per model dof"));
      initial.velocity = Eigen::Map<const Eigen::VectorXd>(v.data(), dofs);
    }
  } else {
    for (const char* key : {"node", "dof"}) {
      if (s.Has(key)) {
        s.Fail(key, std::string("initial.") + key + " only with initial.static_tip_force (or static_force)",
               Describe(s.Node(key)));
      }
    }
  }
  return initial;
}

SensorSpec ReadSensors(const CaseDocument::Impl& doc, const CaseSpec& spec) {
  const Section s = SubSection(doc, "sensors", false);
  SensorSpec sensors;
  const bool beam = spec.model.type == ModelType::kBeam;
  const std::string quantity =
      s.Choice("quantity", {"displacement", "velocity", "acceleration"}, "displacement");
  sensors.quantity = quantity == "displacement"
                         ? SensorQuantity::kDisplacement
                         : (quantity == "velocity" ? SensorQuantity::kVelocity
                                                   : SensorQuantity::kAcceleration);
  // Under [base]: accelerometers measure the absolute acceleration; a
  // displacement or velocity is relative to the supports (the base's own is
  // not known from its measured acceleration).
  const bool acceleration = sensors.quantity == SensorQuantity::kAcceleration;
  const std::string reference =
      s.Choice("reference", {"absolute", "relative"}, acceleration ? "absolute" : "relative");
  if (!acceleration && reference == "absolute") {
    s.Fail("reference",
           "\"relative\" for a displacement or velocity (\"absolute\" is for quantity = "
           "\"acceleration\": the base's own motion is not known from its acceleration)",
           "\"absolute\"");
  }
  sensors.reference = reference == "absolute" ? SensorReference::kAbsolute : SensorReference::kRelative;
  if (!beam) {
    for (const char* key : {"dof", "nodes"}) {
      if (s.Has(key)) {
        s.Fail(key, "sensors.dofs (model dofs) for imported matrices", Describe(s.Node(key)));
      }
    }
  }
  sensors.dof = s.Choice("dof", {"w", "theta"}, "w") == "w" ? SensorDof::kW : SensorDof::kTheta;
  if (s.Has("nodes") && s.Has("dofs")) s.Fail("dofs", "either sensors.nodes or sensors.dofs", "both");
  std::set<long long> seen;
  if (s.Has("dofs")) {
    for (const long long d : s.IntegerArray("dofs", 0, {1, spec.dofs()})) {
      if (!seen.insert(d).second) {
        s.Fail("dofs", "distinct dof numbers", "dof " + std::to_string(d) + " twice");
      }
      sensors.dofs.push_back(static_cast<int>(d));
    }
  } else if (!beam) {
    for (int i = 1; i <= spec.dofs(); ++i) sensors.dofs.push_back(i);
  } else if (s.Has("nodes")) {
    const auto nodes = s.IntegerArray("nodes", 0, {LowestNode(spec.beam), spec.beam.elements});
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (!seen.insert(nodes[i]).second) {
        s.Fail("nodes", "distinct node numbers", "node " + std::to_string(nodes[i]) + " twice");
      }
      if (BeamDof(spec.beam, static_cast<int>(nodes[i]), sensors.dof) < 0) {
        s.Fail("nodes." + std::to_string(i),
               std::string("a node whose ") + (sensors.dof == SensorDof::kW ? "w" : "theta") +
                   " is free (not held by the end condition)",
               std::to_string(nodes[i]));
      }
      sensors.nodes.push_back(static_cast<int>(nodes[i]));
    }
  } else {
    for (int i = 0; i <= spec.beam.elements; ++i) {
      if (BeamDof(spec.beam, i, sensors.dof) >= 0) sensors.nodes.push_back(i);
    }
  }
  const std::size_t count = sensors.dofs.empty() ? sensors.nodes.size() : sensors.dofs.size();
  if (s.Has("names")) {
    sensors.names = s.StringArray("names", count);
    std::set<std::string> names;
    for (std::size_t i = 0; i < sensors.names.size(); ++i) {
      CheckName(s, "names." + std::to_string(i), sensors.names[i]);
      if (!names.insert(sensors.names[i]).second) {
        s.Fail("names", "distinct channel names", TomlString(sensors.names[i]) + " twice");
      }
    }
  } else if (!beam && spec.model.matrices && !spec.model.matrices->labels.empty()) {
    for (const int d : sensors.dofs) sensors.names.push_back(spec.model.matrices->labels[d - 1]);
  }
  return sensors;
}

void ReadMasses(const CaseDocument::Impl& doc, CaseSpec* spec) {
  for (const Section& s : Tables(doc, "mass")) {
    PointMassSpec m;
    m.node = static_cast<int>(s.Integer("node", {0, spec->beam.elements}));
    m.mass_kg = s.Real("mass", NonNegative("kg"), 0.0);
    m.inertia_kg_m2 = s.Real("inertia", NonNegative("kg m^2"), 0.0);
    if (!s.Has("mass") && !s.Has("inertia")) s.FailSection("mass and/or inertia", "neither");
    spec->masses.push_back(m);
  }
}

void ReadSprings(const CaseDocument::Impl& doc, CaseSpec* spec) {
  for (const Section& s : Tables(doc, "spring")) {
    SpringSpec k;
    k.node = static_cast<int>(s.Integer("node", {0, spec->beam.elements}));
    k.dof = s.Choice("dof", {"w", "theta"}, "w") == "w" ? SensorDof::kW : SensorDof::kTheta;
    k.stiffness = s.Real("stiffness", NonNegative(k.dof == SensorDof::kW ? "N/m" : "N m/rad"), 0.0);
    k.damping = s.Real("damping", NonNegative(k.dof == SensorDof::kW ? "N s/m" : "N m s/rad"), 0.0);
    if (!s.Has("stiffness") && !s.Has("damping")) s.FailSection("stiffness and/or damping", "neither");
    if (BeamDof(spec->beam, k.node, k.dof) < 0) {
      s.Fail("node", "a node whose spring dof is free (not held by the end condition)",
             std::to_string(k.node));
    }
    spec->springs.push_back(k);
  }
}

void ReadImported(const CaseDocument::Impl& doc, const Section& s, CaseSpec* spec) {
  s.OnlyKeys({"type", "file", "mass", "stiffness", "damping", "labels"}, "for type \"matrices\"");
  for (const char* table : {"beam", "mass", "spring"}) {
    if (doc.root.get(table) != nullptr) {
      doc.Fail(table, "no [" + std::string(table) + "] with [model] type = \"matrices\"",
               "a " + std::string(table) + " table");
    }
  }
  ModelSpec& m = spec->model;
  m.type = ModelType::kMatrices;
  std::string cache_key;
  ModelFiles files;
  if (s.Has("file")) {
    m.file = s.String("file");
    m.mass = s.OptionalString("mass").value_or("M");
    m.stiffness = s.OptionalString("stiffness").value_or("K");
    m.damping = s.OptionalString("damping").value_or("");
    files.mat_file = ResolvePath(doc, m.file);
    files.mass = m.mass;
    files.stiffness = m.stiffness;
    files.damping = m.damping;
  } else {
    m.mass = s.String("mass");
    m.stiffness = s.String("stiffness");
    m.damping = s.OptionalString("damping").value_or("");
    files.mass = ResolvePath(doc, m.mass);
    files.stiffness = ResolvePath(doc, m.stiffness);
    files.damping = m.damping.empty() ? "" : ResolvePath(doc, m.damping);
  }
  cache_key = files.mat_file + "\n" + files.mass + "\n" + files.stiffness + "\n" + files.damping;
  std::shared_ptr<const ImportedMatrices> matrices;
  {
    std::lock_guard<std::mutex> lock(doc.force_files->mutex);
    auto& cached = doc.force_files->models[cache_key];
    if (!cached) {
      try {
        cached = std::make_shared<const ImportedMatrices>(ReadModelMatrices(files));
      } catch (const std::exception& e) {
        doc.force_files->models.erase(cache_key);
        throw std::invalid_argument(doc.Where(s.key()) + ": " + s.key() + ": " + e.what());
      }
    }
    matrices = cached;
  }
  if (s.Has("labels")) {
    auto copy = std::make_shared<ImportedMatrices>(*matrices);
    copy->labels = s.StringArray("labels", static_cast<std::size_t>(matrices->mass.rows()));
    std::set<std::string> seen;
    for (std::size_t i = 0; i < copy->labels.size(); ++i) {
      const std::string& label = copy->labels[i];
      CheckName(s, "labels." + std::to_string(i), label);
      if (!seen.insert(label).second)
        s.Fail("labels", "distinct labels", TomlString(label) + " twice");
    }
    matrices = std::move(copy);
  }
  m.matrices = std::move(matrices);
}

}  // namespace

void ReadNodeOrDof(const Section& s, const CaseSpec& spec, int* node, int* dof) {
  const int n = spec.dofs();
  if (s.Has("dof")) {
    if (s.Has("node")) s.Fail("dof", "either " + s.key() + ".node or " + s.key() + ".dof", "both");
    *dof = static_cast<int>(s.Integer("dof", {1, n}));
    *node = 0;
    return;
  }
  if (spec.model.type == ModelType::kMatrices) {
    s.Fail("dof", "a model dof in 1.." + std::to_string(n) + " for imported matrices",
           s.Has("node") ? "a node" : "nothing (the key is required)");
  }
  const int elements = spec.beam.elements;
  *node = static_cast<int>(
      s.OptionalInteger("node", {LowestNode(spec.beam), elements}).value_or(elements));
  *dof = 0;
}

void ReadStructure(const CaseDocument::Impl& doc, CaseSpec* spec) {
  const Section model = SubSection(doc, "model", false);
  if (model.Choice("type", {"beam", "matrices"}, "beam") == "matrices") {
    ReadImported(doc, model, spec);
  } else {
    model.OnlyKeys({"type"}, "for type \"beam\" (the model is the [beam] table)");
    spec->beam = ReadBeam(doc);
    ReadMasses(doc, spec);
    ReadSprings(doc, spec);
  }
  spec->damping = ReadDamping(doc, spec->dofs());
  spec->nonlinearities = ReadNonlinearities(doc, *spec);
  spec->initial = ReadInitial(doc, *spec);
  spec->sensors = ReadSensors(doc, *spec);
}

}  // namespace podid::case_detail
