#pragma once
// The validated content of a case file (docs/case-file.md, examples/beam.toml).
// Units are SI throughout.
//
// A model is a beam (the default) or imported matrices ([model] type =
// "matrices"). Beam nodes are numbered 0 (left end) .. elements (right end);
// each node has w (transverse displacement, m) and theta (rotation, rad). The
// model's dofs are the unconstrained ones in the order w_0, theta_0, w_1, ...,
// w_N, theta_N (see BeamDof()): for the default clamped left end, node i >= 1
// has w at 2 (i - 1) and theta at 2 (i - 1) + 1 (TransverseDof()).
// Imported models number their dofs 1..n in the case file (0-based inside).
// A CaseSpec is produced by CaseDocument::ToSpec() (case_file.hpp), which
// checks every range documented here.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "podid/core/conditioning.hpp"

namespace podid {

/// Upper bound on the dofs of any model (beam: 2 (elements + 1); imported: n).
inline constexpr int kMaxModelDofs = 2000002;

enum class BeamEnd { kClamped, kPinned, kFree };

/// One uniform stretch of a beam ([[beam.segment]]).
struct BeamSegmentSpec {
  double length_m = 0.0;           ///< > 0
  int elements = 0;                ///< >= 1
  double youngs_modulus_Pa = 0.0;  ///< > 0
  double density_kg_per_m3 = 0.0;  ///< > 0
  double area_m2 = 0.0;            ///< > 0
  double second_moment_m4 = 0.0;   ///< > 0
};

struct BeamSpec {
  double length_m = 0.0;              ///< > 0 (total length with segments)
  int elements = 0;                   ///< >= 1 Euler-Bernoulli elements (total with segments)
  double youngs_modulus_Pa = 0.0;     ///< > 0 (the first segment's with segments)
  double density_kg_per_m3 = 0.0;     ///< > 0
  double area_m2 = 0.0;               ///< > 0, cross-section area
  double second_moment_m4 = 0.0;      ///< > 0, I = a^2/12 (square) or w h^3/12
  BeamEnd left = BeamEnd::kClamped;   ///< node 0
  BeamEnd right = BeamEnd::kFree;     ///< node `elements`
  /// Consecutive segments from node 0; empty: one uniform segment given by
  /// the fields above.
  std::vector<BeamSegmentSpec> segments;
};

/// A point mass at a beam node: `mass_kg` on w, `inertia_kg_m2` on theta.
struct PointMassSpec {
  int node = 0;
  double mass_kg = 0.0;        ///< >= 0
  double inertia_kg_m2 = 0.0;  ///< >= 0
};

enum class SensorDof { kW, kTheta };

/// A grounded linear spring and dashpot on one dof of a beam node.
struct SpringSpec {
  int node = 0;
  SensorDof dof = SensorDof::kW;
  double stiffness = 0.0;  ///< >= 0, N/m (w) or N m/rad (theta)
  double damping = 0.0;    ///< >= 0, N s/m (w) or N m s/rad (theta)
};

/// An imported linear model: M (SPD), K and C (symmetric), n x n, sparse.
struct ImportedMatrices {
  Eigen::SparseMatrix<double> mass, stiffness, damping;  ///< damping may be 0 x 0 (none)
  std::vector<std::string> labels;                       ///< optional dof names (dim n)
};

enum class ModelType { kBeam, kMatrices };

struct ModelSpec {
  ModelType type = ModelType::kBeam;
  std::string file;      ///< .mat file, or empty for Matrix Market files
  std::string mass, stiffness, damping;  ///< .mat variable names, or .mtx paths
  /// Filled by ToSpec() (shared by copies of the spec: read once per document).
  std::shared_ptr<const ImportedMatrices> matrices;
};

enum class DampingType { kNone, kRayleigh };

/// Rayleigh damping C = alpha M + beta K, given either directly or as the
/// damping ratios of two modes of the linear beam:
/// zeta_i = alpha / (2 omega_i) + beta omega_i / 2.
struct DampingSpec {
  DampingType type = DampingType::kNone;
  bool from_modal_ratios = false;
  double alpha_per_s = 0.0;             ///< used when !from_modal_ratios
  double beta_s = 0.0;                  ///< used when !from_modal_ratios
  std::array<double, 2> modal_ratios{};  ///< zeta of the two modes, in [0, 1)
  std::array<int, 2> modes{1, 2};        ///< 1-based linear mode numbers, distinct
};

enum class NonlinearType {
  kCubic,       ///< f = -k3 w^3
  kPolynomial,  ///< f = -(k1 w + k2 w^2 + k3 w^3)
  kGap,         ///< clearance: f = -k_c (w - g) for w > g, -k_c (w + g) for w < -g, else 0
  kFriction,    ///< regularised dry friction: f = -mu N tanh(v / v_reg)
};

/// One nonlinear element on the transverse (w) dof of `node`, or on the model
/// dof `dof` (1-based) when dof > 0. f is the force the element applies to
/// that dof. A joint (node2 >= 0 or dof2 > 0) acts on the relative
/// displacement w = x_i - x_j and velocity, applying f to i and -f to j.
struct NonlinearitySpec {
  NonlinearType type = NonlinearType::kCubic;
  int node = 0;
  int node2 = -1;  ///< joint: the second node (w dof); -1: grounded
  int dof = 0;     ///< 1-based model dof; 0: from `node`
  int dof2 = 0;    ///< joint: the second 1-based model dof; 0: grounded (or node2)
  double k1_N_per_m = 0.0;              ///< polynomial
  double k2_N_per_m2 = 0.0;             ///< polynomial
  double k3_N_per_m3 = 0.0;             ///< cubic, polynomial
  double gap_m = 0.0;                   ///< gap, >= 0
  double contact_stiffness_N_per_m = 0.0;  ///< gap, > 0
  double friction_coefficient = 0.0;    ///< friction: mu >= 0
  double normal_force_N = 0.0;          ///< friction: N >= 0
  double regularisation_velocity_m_per_s = 0.0;  ///< friction: v_reg > 0
};

enum class InitialType {
  kRest,         ///< x = 0, v = 0
  kStaticForce,  ///< static deflection under a force at a node, released with v = 0
  kExplicit,     ///< displacement and velocity given (dim n_dofs each)
};

struct InitialSpec {
  InitialType type = InitialType::kRest;
  double static_force_N = 0.0;  ///< kStaticForce: transverse force
  int static_force_node = 0;    ///< kStaticForce: node, defaults to the right end (node `elements`)
  int static_force_dof = 0;     ///< kStaticForce: 1-based model dof; 0: from the node
  Eigen::VectorXd displacement;  ///< kExplicit: (dim n_dofs), m and rad
  Eigen::VectorXd velocity;      ///< kExplicit: (dim n_dofs), m/s and rad/s
};

enum class ForceType { kNone, kHarmonic, kSweep, kFile, kChannel };

/// The time history of an excitation, as a [force] or [base] table gives it,
/// in the unit of its use: N for a force (ForceSpec::history_N), m/s^2 for
/// the base (BaseSpec::history_m_per_s2); "unit" below is that unit. t is the
/// simulation's time from its start (time.start_s), t_abs = time.start_s + t
/// the record's time:
///  harmonic: h = A sin(2 pi f t);
///  sweep:    h = A sin(2 pi (f0 t + (f1 - f0) t^2 / (2 T))), T = duration;
///  file:     h = gain x (a CSV column at t_abs) + offset, linearly interpolated
///            (band-limited with integrator.substeps > 1), 0 outside the column's time;
///  channel:  h = gain x (a channel of the [data] file at t_abs) + offset, the same way.
/// gain and offset are applied when the load is built (BuildLoad, load.hpp), so
/// that an identification changes them without re-reading the file (kLoad).
struct ExcitationHistory {
  ForceType type = ForceType::kNone;
  double amplitude = 0.0;           ///< harmonic, sweep: A (unit)
  double frequency_Hz = 0.0;        ///< harmonic
  double start_frequency_Hz = 0.0;  ///< sweep
  double end_frequency_Hz = 0.0;    ///< sweep
  std::string file;                 ///< file: CSV path (relative to the case file)
  std::string column;               ///< file: column name
  std::string channel;              ///< channel: channel name in the [data] file
  double gain = 1.0;                ///< file, channel: unit per unit of the column (e.g. N/V)
  double offset = 0.0;              ///< file, channel: added after the gain (unit)
  Eigen::VectorXd file_time_s;      ///< file, channel: the column's time (s), filled by ToSpec()
  Eigen::VectorXd file_values;      ///< file, channel: the column, in its unit, filled by ToSpec()
};

/// External transverse force at `node` (or model dof `dof`): f(t) = history_N.
struct ForceSpec {
  int node = 0;
  int dof = 0;                  ///< 1-based model dof; 0: the node's w
  ExcitationHistory history_N;  ///< f(t) in N (gain in N per unit of the column)
};

/// Most [[force]] tables a case may have (each adds a load history of the
/// integration grid's length to a simulation's memory).
inline constexpr int kMaxForces = 64;

/// Base (support) excitation: the supports move with the ground acceleration
/// a_g(t) (m/s^2) and the structure is integrated in coordinates u_r relative
/// to them (the support is the ground of springs and grounded elements):
///   M u_r'' + C u_r' + K u_r + f_nl(u_r) = -M r a_g(t) + (the [force]s),
/// r the rigid-body motion of the dofs when the base moves by 1 (beam: 1 on
/// every free w, 0 on theta, with the supports' consistent-mass coupling,
/// i.e. -(M_full r_full) restricted to the free dofs; imported models: the
/// `influence` vector).
struct BaseSpec {
  ExcitationHistory history_m_per_s2;  ///< a_g(t) in m/s^2 (gain in m/s^2 per unit of the column)
  /// Imported models: r (dim n_dofs), from `influence` or `influence_file`;
  /// empty for beams (their r is built from the supports).
  Eigen::VectorXd influence;
  std::string influence_file;  ///< the file r was read from (for messages), or ""
};

struct TimeSpec {
  double duration_s = 0.0;  ///< > 0
  double step_s = 0.0;      ///< > 0, <= duration
  /// Record time of the first sample (s): the simulation starts there from
  /// the initial state; its sensors are stamped start + n step, and file and
  /// channel forces are read at that time. Default 0.
  double start_s = 0.0;
  /// Number of samples including t = 0: round(duration / step) + 1.
  int samples() const;
};

enum class SensorQuantity { kDisplacement, kVelocity, kAcceleration };

/// What the sensors measure under base excitation: the motion relative to the
/// supports, or the absolute one (the support's added back). Absolute is
/// available for accelerations only (u_r'' + r a_g, as accelerometers
/// measure): a measured acceleration does not fix the base's displacement.
/// Without [base] both are the same.
enum class SensorReference { kRelative, kAbsolute };

struct SensorSpec {
  SensorDof dof = SensorDof::kW;
  std::vector<int> nodes;  ///< beam nodes; default every node whose `dof` is free
  std::vector<int> dofs;   ///< 1-based model dofs; when non-empty, replaces `nodes`
  std::vector<std::string> names;  ///< channel names; empty: the defaults below
  SensorQuantity quantity = SensorQuantity::kDisplacement;
  /// Default: absolute for accelerations, relative for the rest.
  SensorReference reference = SensorReference::kRelative;
  /// `names` if given, else "w1".."w6" (or "theta1"...) for nodes, "x3" for dofs.
  std::vector<std::string> ChannelNames() const;
};

struct NoiseSpec {
  double relative = 0.0;  ///< std = relative * max |x(t = 0)| over the sensors, >= 0
  unsigned long long seed = 1;
};

enum class IntegratorType {
  kModifiedNewmark,  ///< the paper's condensed Newmark (sec. 4.1), default
  kNewmark,          ///< Newton-Raphson on all dofs (reference)
};

struct IntegratorSpec {
  IntegratorType type = IntegratorType::kModifiedNewmark;
  double gamma = 0.5;   ///< Newmark gamma, in [0.5, 1]
  double beta = 0.25;   ///< Newmark beta, in (0, 0.5]; unconditionally stable for beta >= gamma / 2
  double tolerance = 1e-10;  ///< Newton: relative residual tolerance, in (0, 1)
  int max_iterations = 50;   ///< Newton iterations per step, in [1, 10^6]
  /// Newmark steps per sample: the integrator runs at time.step / substeps
  /// and the output keeps every substeps-th state. In [1, kMaxSubsteps].
  int substeps = 1;
};

inline constexpr int kMaxSubsteps = 1000;

/// One identified parameter: the case value at `key` is scale * value.
struct ParameterSpec {
  std::string name;   ///< e.g. "knl"
  std::string key;    ///< e.g. "nonlinearity.0.k3"
  double scale = 1.0;
  double start = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};

/// [data]: the recording a case is identified from and its conditioning.
struct DataSpec {
  std::string file;      ///< resolved path; "" when none (given on the command line)
  std::string variable;  ///< .mat variable or struct
  double rate_Hz = 0.0;  ///< sampling rate of a file without time (or step_s)
  double step_s = 0.0;
  /// channels: the file's channels, in the order of the case's sensors (they
  /// are renamed to the sensors' names). The rest applies to the measured
  /// record and, identically, to the simulated sensors.
  ConditioningOptions conditioning;
};

struct CaseSpec {
  std::string source;  ///< the file it came from (for messages)
  ModelSpec model;
  BeamSpec beam;        ///< model.type == kBeam
  std::vector<PointMassSpec> masses;
  std::vector<SpringSpec> springs;
  DampingSpec damping;
  std::vector<NonlinearitySpec> nonlinearities;
  InitialSpec initial;
  ForceSpec force;                ///< the single [force] table (type kNone when absent)
  std::vector<ForceSpec> forces;  ///< [[force]] tables (at most kMaxForces; none with [force])
  BaseSpec base;                  ///< [base] (type kNone when absent)
  TimeSpec time;
  SensorSpec sensors;
  NoiseSpec noise;
  IntegratorSpec integrator;
  std::vector<ParameterSpec> parameters;
  DataSpec data;

  /// Number of model dofs (beam: its unconstrained dofs; imported: n).
  int dofs() const;
};

/// Index of node's transverse dof among the free dofs (node in 1..elements),
/// for a beam clamped at node 0.
inline int TransverseDof(int node) { return 2 * (node - 1); }
/// Index of node's rotation dof among the free dofs (node in 1..elements),
/// for a beam clamped at node 0.
inline int RotationDof(int node) { return 2 * (node - 1) + 1; }

/// Index of a beam node's dof among the model dofs, or -1 when the boundary
/// condition holds it (clamped: w and theta; pinned: w). node in 0..elements.
int BeamDof(const BeamSpec& beam, int node, SensorDof which);
/// Number of unconstrained dofs of the beam.
int BeamDofCount(const BeamSpec& beam);
const char* ToString(BeamEnd end);

}  // namespace podid
