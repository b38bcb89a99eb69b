#pragma once
// Imported linear models: M, K and optionally C from a MATLAB .mat file (dense
// or sparse variables) or from Matrix Market files (coordinate or array,
// real or integer, general or symmetric). Units are SI.

#include <Eigen/SparseCore>
#include <string>

#include "podid/core/case_spec.hpp"

namespace podid {

/// Largest dimension n of an imported matrix.
inline constexpr int kMaxImportedDofs = 1000000;
/// Largest number of stored entries of an imported matrix.
inline constexpr long long kMaxImportedEntries = 100000000;

/// Where an imported model's matrices are. With `mat_file`, `mass`,
/// `stiffness` and `damping` are variable names in it; without, they are
/// Matrix Market paths. An empty `damping` means no damping matrix.
struct ModelFiles {
  std::string mat_file;
  std::string mass, stiffness, damping;
};

/// Reads the matrices (labels left empty). Throws std::invalid_argument naming
/// the file (and line or variable) for a missing file or variable, a
/// malformed header or entry, an index out of range, a non-finite value, a
/// size above the bounds above, or matrices of different sizes.
ImportedMatrices ReadModelMatrices(const ModelFiles& files);

/// One Matrix Market file (same errors).
Eigen::SparseMatrix<double> ReadMatrixMarket(const std::string& path);

/// Writes `a` as "%%MatrixMarket matrix coordinate real general" with 17
/// significant digits (round-trips exactly), atomically.
void WriteMatrixMarket(const std::string& path, const Eigen::SparseMatrix<double>& a);

}  // namespace podid
