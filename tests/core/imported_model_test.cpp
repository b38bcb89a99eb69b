// Imported linear models ([model] type = "matrices"): a .mat (written here by
// a minimal level-5 writer, independent of libmatio) and a Matrix Market copy
// of the reference beam respond as the built-in beam; a joint between two
// dofs equals the grounded element when its other side cannot move; input
// errors name the file and what was expected.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "mat5_file.hpp"
#include "podid/core/beam_model.hpp"
#include "podid/core/case_file.hpp"
#include "podid/core/model_io.hpp"
#include "podid/core/simulate.hpp"
#include "reference_case.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ReferenceCase;
using testing::TempDir;

using testing::Mat5Append;
using testing::Mat5Pad;
using testing::Mat5Tag;

// A sparse variable: flags (class mxSPARSE_CLASS (5), nzmax), dimensions,
// name, row indices and column pointers (miINT32), values (`values_type`:
// miDOUBLE, 9, unless a test corrupts it).
std::string MatSparseVariable(const std::string& name,
                              const Eigen::MatrixXd& dense,
                              std::uint32_t values_type = 9) {
  std::vector<std::int32_t> ir, jc{0};
  std::vector<double> pr;
  for (Eigen::Index c = 0; c < dense.cols(); ++c) {
    for (Eigen::Index r = 0; r < dense.rows(); ++r) {
      if (dense(r, c) == 0.0) continue;
      ir.push_back(static_cast<std::int32_t>(r));
      pr.push_back(dense(r, c));
    }
    jc.push_back(static_cast<std::int32_t>(ir.size()));
  }
  std::string body;
  Mat5Tag(&body, 6, 8);
  const std::uint32_t flags[2] = {5, static_cast<std::uint32_t>(ir.size())};
  Mat5Append(&body, flags, 8);
  Mat5Tag(&body, 5, 8);
  const std::int32_t dims[2] = {static_cast<std::int32_t>(dense.rows()),
                                static_cast<std::int32_t>(dense.cols())};
  Mat5Append(&body, dims, 8);
  Mat5Tag(&body, 1, static_cast<std::uint32_t>(name.size()));
  body += name;
  Mat5Pad(&body);
  Mat5Tag(&body, 5, static_cast<std::uint32_t>(4 * ir.size()));
  Mat5Append(&body, ir.data(), 4 * ir.size());
  Mat5Pad(&body);
  Mat5Tag(&body, 5, static_cast<std::uint32_t>(4 * jc.size()));
  Mat5Append(&body, jc.data(), 4 * jc.size());
  Mat5Pad(&body);
  Mat5Tag(&body, values_type, static_cast<std::uint32_t>(8 * pr.size()));
  Mat5Append(&body, pr.data(), 8 * pr.size());
  std::string element;
  Mat5Tag(&element, 14, static_cast<std::uint32_t>(body.size()));
  return element + body;
}

void WriteMatFile(const std::string& path, const std::string& variables) {
  std::ofstream(path, std::ios::binary)
      << testing::Mat5Header("MATLAB 5.0 MAT-file, written by podid's imported_model_test") +
             variables;
}

void WriteMat(const std::string& path,
              const std::vector<std::pair<std::string, Eigen::MatrixXd>>& vars) {
  std::string variables;
  for (const auto& [name, a] : vars) variables += testing::Mat5DoubleVariable(name, a);
  WriteMatFile(path, variables);
}

/// The reference case's body after [beam] as an imported model: the same
/// damping, nonlinearity (dof 11 = w6), release, time and sensors.
std::string ImportedReference(const std::string& model_table) {
  return model_table +
         "\n[damping]\ntype = \"rayleigh\"\nmodal_ratios = [0.01, 0.01]\n"
         "[[nonlinearity]]\ntype = \"cubic\"\ndof = 11\nk3 = 5.0e9\n"
         "[initial]\nstatic_force = 20.0\ndof = 11\n"
         "[time]\nduration = 0.1\nstep = 2.0e-4\n"
         "[sensors]\ndofs = [1, 3, 5, 7, 9, 11]\nnames = [\"w1\", \"w2\", \"w3\", \"w4\", \"w5\", \"w6\"]\n";
}

TEST(ImportedModel, MatAndMatrixMarketCopiesRespondAsTheBuiltInBeam) {
  // The same matrices, hence the same response; 1e-12 leaves room for the
  // order of sparse-to-dense conversion (none is expected).
  constexpr double kRelativeTolerance = 1e-12;
  const CaseSpec reference = ReferenceCase();
  const BeamModel beam = BeamModel::BuildLinear(reference.beam);
  const SimulationResult expected = Simulate(reference);
  ASSERT_TRUE(expected.summary.IsSolutionUsable());

  TempDir dir;
  WriteMat(dir.File("beam.mat"), {{"Mbeam", beam.DenseMass()}, {"Kbeam", beam.DenseStiffness()}});
  WriteMatFile(dir.File("sparse.mat"), MatSparseVariable("Mbeam", beam.DenseMass()) +
                                           MatSparseVariable("Kbeam", beam.DenseStiffness()));
  WriteMatrixMarket(dir.File("M.mtx"), beam.mass());
  WriteMatrixMarket(dir.File("K.mtx"), beam.stiffness());
  const std::string tables[] = {
      "[model]\ntype = \"matrices\"\nfile = \"beam.mat\"\nmass = \"Mbeam\"\nstiffness = \"Kbeam\"",
      "[model]\ntype = \"matrices\"\nfile = \"sparse.mat\"\nmass = \"Mbeam\"\nstiffness = "
      "\"Kbeam\"",
      "[model]\ntype = \"matrices\"\nmass = \"M.mtx\"\nstiffness = \"K.mtx\"",
  };
  for (const std::string& table : tables) {
    SCOPED_TRACE(table);
    const CaseSpec spec =
        CaseDocument::Parse(ImportedReference(table), dir.File("case.toml"), dir.path()).ToSpec();
    ASSERT_EQ(spec.dofs(), 12);
    const SimulationResult imported = Simulate(spec);
    ASSERT_TRUE(imported.summary.IsSolutionUsable()) << imported.summary.message;
    EXPECT_EQ(imported.sensors.channel_names, expected.sensors.channel_names);
    const double scale = expected.sensors.values.cwiseAbs().maxCoeff();
    EXPECT_TRUE(testing::ExpectMatricesNear(imported.sensors.values, expected.sensors.values,
                                            kRelativeTolerance * scale));
  }
}

TEST(ImportedModel, SymmetricMatrixMarketAndLabels) {
  TempDir dir;
  dir.Write("m.mtx", "%%MatrixMarket matrix coordinate real symmetric\n% a comment\n2 2 3\n1 1 2.0\n2 1 0.5\n2 2 1.0\n");
  dir.Write("k.mtx", "%%MatrixMarket matrix array real general\n2 2\n4\n-1\n-1\n3\n");
  const Eigen::SparseMatrix<double> m = ReadMatrixMarket(dir.File("m.mtx"));
  EXPECT_EQ(Eigen::MatrixXd(m), (Eigen::MatrixXd(2, 2) << 2.0, 0.5, 0.5, 1.0).finished());
  const CaseSpec spec = CaseDocument::Parse(
      "[model]\ntype = \"matrices\"\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\nlabels = [\"left\", \"right\"]\n"
      "[time]\nduration = 0.1\nstep = 0.01\n",
      "case.toml", dir.path()).ToSpec();
  EXPECT_EQ(spec.sensors.ChannelNames(), (std::vector<std::string>{"left", "right"}));
  EXPECT_EQ(Eigen::MatrixXd(BeamModel::Build(spec).stiffness()),
            (Eigen::MatrixXd(2, 2) << 4, -1, -1, 3).finished());
}

TEST(ImportedModel, RejectsBadMatrices) {
  TempDir dir;
  dir.Write("m.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n2 2 1.0\n");
  dir.Write("neg.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n2 2 -1.0\n");
  dir.Write("asym.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 2.0\n1 2 1.0\n2 2 2.0\n");
  dir.Write("big.mtx", "%%MatrixMarket matrix coordinate real general\n3 3 1\n1 1 1.0\n");
  dir.Write("bad.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 3 1.0\n");
  dir.Write("nan.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 nan\n");
  dir.Write("short.mtx", "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n");
  dir.Write("huge.mtx", "%%MatrixMarket matrix coordinate real general\n2000000 2000000 1\n1 1 1.0\n");
  auto load = [&](const std::string& mass, const std::string& stiffness, const std::string& extra = "") {
    const CaseSpec spec = CaseDocument::Parse("[model]\ntype = \"matrices\"\nmass = \"" + mass +
                                                  "\"\nstiffness = \"" + stiffness + "\"\n" + extra +
                                                  "[time]\nduration = 0.1\nstep = 0.01\n",
                                              "case.toml", dir.path()).ToSpec();
    return BeamModel::Build(spec);
  };
  struct Rejection {
    const char* mass;
    const char* stiffness;
    const char* extra;  // TOML after the [model] keys
    const char* needle;
  };
  const Rejection rejections[] = {
      {"neg.mtx", "m.mtx", "", "case.toml: model.mass: expected a positive definite mass matrix"},
      {"m.mtx", "neg.mtx", "",
       "case.toml: model.stiffness: expected a positive semi-definite stiffness matrix"},
      {"m.mtx", "m.mtx", "damping = \"neg.mtx\"\n",
       "case.toml: model.damping: expected a positive semi-definite damping matrix"},
      {"m.mtx", "asym.mtx", "", "case.toml: model.stiffness: expected a finite symmetric matrix"},
      {"m.mtx", "big.mtx", "",
       "big.mtx: expected a square matrix of the mass matrix's size 2 x 2, got 3 x 3"},
      {"m.mtx", "bad.mtx", "", "bad.mtx:3: expected an index in 1..2, got 3"},
      {"m.mtx", "nan.mtx", "", "nan.mtx:3: expected a finite number"},
      {"m.mtx", "short.mtx", "", "short.mtx: expected 2 entries, got 1 (the file ends)"},
      {"m.mtx", "huge.mtx", "",
       "huge.mtx:2: expected dimensions in [1, 1000000], got 2000000 x 2000000"},
      {"m.mtx", "missing.mtx", "",
       "missing.mtx: expected a readable Matrix Market file, got a file that cannot be opened"},
      {"m.mtx", "m.mtx", "[sensors]\nnodes = [1]\n",
       "sensors.nodes: expected sensors.dofs (model dofs) for imported matrices"},
      {"m.mtx", "m.mtx", "[[nonlinearity]]\ntype = \"cubic\"\nk3 = 1\n",
       "nonlinearity.0: expected dof = i or dofs = [i, j] (model dofs 1..2) for imported "
       "matrices, got neither"},
      {"m.mtx", "m.mtx", "[[nonlinearity]]\ntype = \"cubic\"\ndofs = [1, 3]\nk3 = 1\n",
       "nonlinearity.0.dofs.1: expected an integer in [1, 2], got 3"},
      {"m.mtx", "m.mtx", "[initial]\nstatic_force = 1.0\n",
       "initial.dof: expected a model dof in 1..2 for imported matrices, got nothing"},
      {"m.mtx", "m.mtx", "labels = [\"a\"]\n",
       "model.labels: expected an array of 2 strings, got an array of 1"},
  };
  for (const Rejection& r : rejections) {
    SCOPED_TRACE(std::string(r.mass) + ", " + r.stiffness + ", " + r.extra);
    PODID_EXPECT_THROW_WITH(load(r.mass, r.stiffness, r.extra), std::invalid_argument, r.needle);
  }

  // A v7.3 file gets ReadMat's checks too: 3e8 doubles declared, none stored.
  ModelFiles v73;
  v73.mat_file = testing::DataPath("readers/v73_unwritten_3e8.mat");
  v73.mass = "w";
  v73.stiffness = "w";
  PODID_EXPECT_THROW_WITH(ReadModelMatrices(v73), std::invalid_argument,
                          "v73_unwritten_3e8.mat: dataset '/w': expected data stored in the file");

  // A sparse matrix whose values are an miUTF8 element (type 16): libmatio
  // converts none to double and would return them uninitialised.
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(2, 2);
  WriteMatFile(dir.File("utf8.mat"),
               MatSparseVariable("M", identity) + MatSparseVariable("K", identity, 16));
  PODID_EXPECT_THROW_WITH(
      BeamModel::Build(
          CaseDocument::Parse("[model]\ntype = \"matrices\"\nfile = \"utf8.mat\"\nmass = \"M\"\n"
                              "stiffness = \"K\"\n[time]\nduration = 0.1\nstep = 0.01\n",
                              "case.toml", dir.path())
              .ToSpec()),
      std::invalid_argument,
      "utf8.mat: byte 344: expected the real part: a whole number of values in an element of a "
      "numeric type "
      "(1-7, 9, 12 or 13), got an element of type 16 and 16 bytes");
}

/// The reference beam's M and K with a 13th dof of mass 1e30 kg and no
/// stiffness: a dof that cannot move in 0.1 s (its acceleration is 1e-30 of
/// the beam's).
TEST(Joint, EqualsTheGroundedElementWhenItsOtherSideIsFixed) {
  // The heavy dof moves by ~1e-30 m, so both solve the same equations; they
  // agree to the Newton tolerance (1e-13 here): the grounded element is
  // solved by the scalar Newton path, the joint by the 2-dof one.
  constexpr double kRelativeTolerance = 1e-9;
  const CaseSpec reference = ReferenceCase({"damping.modal_ratios=[0.0, 0.0]"});
  const BeamModel beam = BeamModel::BuildLinear(reference.beam);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(13, 13), k = Eigen::MatrixXd::Zero(13, 13);
  m.topLeftCorner(12, 12) = beam.DenseMass();
  k.topLeftCorner(12, 12) = beam.DenseStiffness();
  m(12, 12) = 1e30;
  TempDir dir;
  WriteMatrixMarket(dir.File("M.mtx"), m.sparseView());
  WriteMatrixMarket(dir.File("K.mtx"), k.sparseView());
  const std::string common =
      "[damping]\ntype = \"rayleigh\"\nalpha = 3.0\nbeta = 1e-5\n"
      "[initial]\nvelocity = [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5, 0, 0]\n"
      "[time]\nduration = 0.1\nstep = 2.0e-4\n[sensors]\ndofs = [1, 5, 11, 13]\n"
      "[integrator]\ntolerance = 1e-13\n";
  const std::string model = "[model]\ntype = \"matrices\"\nmass = \"M.mtx\"\nstiffness = \"K.mtx\"\n";
  for (const char* type : {"cubic\"\nk3 = 5.0e9", "friction\"\nmu = 0.3\nnormal_force = 10\nvelocity_scale = 0.05",
                           "gap\"\ngap = 1e-4\nstiffness = 1e5"}) {
    SCOPED_TRACE(type);
    const std::string element = std::string("[[nonlinearity]]\ntype = \"") + type + "\n";
    auto run = [&](const std::string& where) {
      const CaseSpec spec = CaseDocument::Parse(model + common + element + where, "case.toml", dir.path()).ToSpec();
      SimulationResult r = Simulate(spec);
      EXPECT_TRUE(r.summary.IsSolutionUsable()) << r.summary.message;
      return r.sensors.values;
    };
    const Eigen::MatrixXd grounded = run("dof = 11\n");
    const Eigen::MatrixXd joint = run("dofs = [11, 13]\n");
    const Eigen::MatrixXd reversed = run("dofs = [13, 11]\n");  // f on 13, -f on 11: the same
    const double scale = grounded.cwiseAbs().maxCoeff();
    EXPECT_TRUE(testing::ExpectMatricesNear(joint, grounded, kRelativeTolerance * scale));
    EXPECT_TRUE(testing::ExpectMatricesNear(reversed, grounded, kRelativeTolerance * scale));
    EXPECT_LT(joint.col(3).cwiseAbs().maxCoeff(), 1e-20);
  }
}

TEST(Joint, BeamNodesAndFullNewtonAgree) {
  // A joint between two beam nodes (nodes = [3, 6]) with both integrators:
  // the modified method (condensed on 2 nonlinear dofs, a non-diagonal
  // tangent) and Newton on all dofs solve the same equations, to the Newton
  // tolerance 1e-12 times the conditioning of a step (~1e3).
  constexpr double kRelativeTolerance = 1e-8;
  std::string text = testing::ReadText(testing::ExamplePath("beam.toml"));
  const std::string grounded = "node = 6\nk3 = 5.0e9";
  ASSERT_NE(text.find(grounded), std::string::npos);
  text.replace(text.find(grounded), grounded.size(), "nodes = [3, 6]\nk3 = 5.0e12");
  CaseDocument doc = CaseDocument::Parse(text, "joint.toml");
  doc.Set("integrator.tolerance", "1e-12");
  const CaseSpec modified = doc.ToSpec();
  ASSERT_EQ(modified.nonlinearities.at(0).node2, 6);
  doc.Set("integrator.type", "newmark");
  const SimulationResult a = Simulate(modified), b = Simulate(doc.ToSpec());
  ASSERT_TRUE(a.summary.IsSolutionUsable()) << a.summary.message;
  ASSERT_TRUE(b.summary.IsSolutionUsable()) << b.summary.message;
  EXPECT_EQ(a.summary.nonlinear_dofs, 2);
  const double scale = a.sensors.values.cwiseAbs().maxCoeff();
  EXPECT_TRUE(testing::ExpectMatricesNear(a.sensors.values, b.sensors.values, kRelativeTolerance * scale));
  // The joint changes the response (k3 acts on w3 - w6, not on w6 alone).
  const SimulationResult plain = Simulate(testing::ReferenceCase());
  EXPECT_GT((plain.sensors.values - a.sensors.values).cwiseAbs().maxCoeff(), 1e-3 * scale);
}

}  // namespace
}  // namespace podid
