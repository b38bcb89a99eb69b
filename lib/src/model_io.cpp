// Imported model matrices: .mat (libmatio, after the structural checks of
// mat_structure.hpp) and Matrix Market (a small bounded reader: Eigen's
// loadMarket trusts the header's sizes and does not report malformed lines).
#include "podid/core/model_io.hpp"

#include <matio.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "io_internal.hpp"
#include "io_mat_internal.hpp"
#include "mat_structure.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
namespace {

/// Longest Matrix Market line (bytes): a header or an entry is far shorter.
constexpr std::size_t kMaxLineBytes = 4096;

using Triplets = std::vector<Eigen::Triplet<double>>;

void CheckDimension(long long rows, long long cols, const std::string& where) {
  if (rows < 1 || cols < 1 || rows > kMaxImportedDofs || cols > kMaxImportedDofs) {
    ThrowInvalid(where, "dimensions in [1, " + ToText(kMaxImportedDofs) + "]",
                 ToText(rows) + " x " + ToText(cols));
  }
}

void CheckFinite(double v, const std::string& where) {
  if (!std::isfinite(v)) ThrowInvalid(where, "a finite number", ToText(v));
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool ReadLine(std::istream& in, std::string* line, const std::string& path, long long line_no) {
  line->clear();
  char c;
  while (in.get(c)) {
    if (c == '\n') return true;
    if (line->size() >= kMaxLineBytes) {
      ThrowInvalid(path + ":" + ToText(line_no), "a line of at most 4096 bytes", "a longer line");
    }
    line->push_back(c);
  }
  return !line->empty();
}

/// Parses whitespace-separated numbers of a line into `out` (exactly `count`).
void ParseNumbers(const std::string& line, std::size_t count, double* out, const std::string& where) {
  const char* p = line.data();
  const char* end = p + line.size();
  for (std::size_t k = 0; k < count; ++k) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
    const auto r = std::from_chars(p, end, out[k]);
    if (r.ec != std::errc() || (r.ptr < end && *r.ptr != ' ' && *r.ptr != '\t' && *r.ptr != '\r')) {
      ThrowInvalid(where, ToText(count) + " numbers", "\"" + line + "\"");
    }
    p = r.ptr;
  }
  while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  if (p != end) ThrowInvalid(where, ToText(count) + " numbers", "\"" + line + "\"");
}

long long ToIndex(double v, long long n, const std::string& where) {
  if (!(v >= 1 && v <= static_cast<double>(n) && v == std::floor(v))) {
    ThrowInvalid(where, "an index in 1.." + ToText(n), ToText(v));
  }
  return static_cast<long long>(v);
}

Eigen::SparseMatrix<double> FromMatVariable(mat_t* mat, const std::string& name,
                                            const std::string& path) {
  const std::string where = path + ": variable '" + name + "'";
  const internal::MatVarPtr var = internal::ReadMatVar(mat, name);
  if (!var) ThrowInvalid(where, "a variable of that name", "none");
  if (var->rank != 2 || var->isComplex) {
    ThrowInvalid(where, "a real 2-D matrix", "rank " + ToText(var->rank) + (var->isComplex ? ", complex" : ""));
  }
  const long long rows = static_cast<long long>(var->dims[0]);
  const long long cols = static_cast<long long>(var->dims[1]);
  CheckDimension(rows, cols, where);
  Triplets triplets;
  if (var->class_type == MAT_C_SPARSE) {
    const auto* sp = static_cast<const mat_sparse_t*>(var->data);
    if (sp == nullptr || var->data_type != MAT_T_DOUBLE || sp->njc != static_cast<mat_uint32_t>(cols + 1) ||
        sp->jc == nullptr || (sp->ndata > 0 && (sp->ir == nullptr || sp->data == nullptr))) {
      ThrowInvalid(where, "a real double sparse matrix", "an unreadable sparse matrix");
    }
    const auto* values = static_cast<const double*>(sp->data);
    if (sp->jc[cols] > sp->ndata || sp->jc[cols] > sp->nir) {
      ThrowInvalid(where, "sparse column pointers within the data", ToText(sp->jc[cols]));
    }
    if (static_cast<long long>(sp->jc[cols]) > kMaxImportedEntries) {
      ThrowInvalid(where, "at most " + ToText(kMaxImportedEntries) + " entries", ToText(sp->jc[cols]));
    }
    triplets.reserve(sp->jc[cols]);
    for (long long c = 0; c < cols; ++c) {
      if (sp->jc[c] > sp->jc[c + 1]) ThrowInvalid(where, "increasing column pointers", "a decrease");
      for (mat_uint32_t k = sp->jc[c]; k < sp->jc[c + 1]; ++k) {
        if (sp->ir[k] >= static_cast<mat_uint32_t>(rows)) {
          ThrowInvalid(where, "row indices < " + ToText(rows), ToText(sp->ir[k]));
        }
        CheckFinite(values[k], where);
        triplets.emplace_back(static_cast<int>(sp->ir[k]), static_cast<int>(c), values[k]);
      }
    }
  } else {
    if (rows * cols > kMaxImportedEntries) {
      ThrowInvalid(where, "at most " + ToText(kMaxImportedEntries) + " entries", ToText(rows * cols));
    }
    const std::size_t n = static_cast<std::size_t>(rows * cols);
    const bool is_double = var->data_type == MAT_T_DOUBLE && var->class_type == MAT_C_DOUBLE;
    const bool is_single = var->data_type == MAT_T_SINGLE && var->class_type == MAT_C_SINGLE;
    if ((!is_double && !is_single) || var->data == nullptr ||
        var->nbytes < n * (is_double ? sizeof(double) : sizeof(float))) {
      ThrowInvalid(where, "a real double or single matrix (dense or sparse)", "another class or no data");
    }
    for (long long c = 0; c < cols; ++c) {
      for (long long r = 0; r < rows; ++r) {
        const std::size_t at = static_cast<std::size_t>(r + c * rows);
        const double v = is_double ? static_cast<const double*>(var->data)[at]
                                   : static_cast<const float*>(var->data)[at];
        CheckFinite(v, where);
        if (v != 0.0) triplets.emplace_back(static_cast<int>(r), static_cast<int>(c), v);
      }
    }
  }
  Eigen::SparseMatrix<double> a(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  a.setFromTriplets(triplets.begin(), triplets.end());
  return a;
}

}  // namespace

Eigen::SparseMatrix<double> ReadMatrixMarket(const std::string& path) {
  internal::RequireRegularFile(path, "a readable Matrix Market file");
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowInvalid(path, "a readable Matrix Market file", "a file that cannot be opened");
  std::string line;
  long long line_no = 1;
  if (!ReadLine(in, &line, path, line_no)) ThrowInvalid(path, "a Matrix Market header", "an empty file");
  std::istringstream header(Lower(line));
  std::string banner, object, format, field, symmetry;
  header >> banner >> object >> format >> field >> symmetry;
  const std::string expected =
      "%%MatrixMarket matrix coordinate|array real|integer|double general|symmetric";
  if (banner != "%%matrixmarket" || object != "matrix" || (format != "coordinate" && format != "array") ||
      (field != "real" && field != "integer" && field != "double") ||
      (symmetry != "general" && symmetry != "symmetric")) {
    ThrowInvalid(path + ":1", expected, "\"" + line + "\"");
  }
  const bool coordinate = format == "coordinate", symmetric = symmetry == "symmetric";
  // Comments, then the size line.
  do {
    ++line_no;
    if (!ReadLine(in, &line, path, line_no)) ThrowInvalid(path, "a size line", "the end of the file");
  } while (line.empty() || line[0] == '%');
  double size[3] = {0, 0, 0};
  ParseNumbers(line, coordinate ? 3 : 2, size, path + ":" + ToText(line_no));
  for (double v : size) {
    if (!(v >= 0 && v <= 1e15 && v == std::floor(v))) {
      ThrowInvalid(path + ":" + ToText(line_no), "non-negative integer sizes", "\"" + line + "\"");
    }
  }
  const long long rows = static_cast<long long>(size[0]), cols = static_cast<long long>(size[1]);
  CheckDimension(rows, cols, path + ":" + ToText(line_no));
  if (symmetric && rows != cols) ThrowInvalid(path + ":" + ToText(line_no), "a square symmetric matrix", "\"" + line + "\"");
  const long long entries =
      coordinate ? static_cast<long long>(size[2])
                 : (symmetric ? rows * (rows + 1) / 2 : rows * cols);
  if (entries > kMaxImportedEntries) {
    ThrowInvalid(path + ":" + ToText(line_no), "at most " + ToText(kMaxImportedEntries) + " entries",
                 ToText(entries));
  }
  Triplets triplets;
  long long r = 0, c = 0;  // array format: column-major position
  for (long long k = 0; k < entries; ++k) {
    do {
      ++line_no;
      if (!ReadLine(in, &line, path, line_no)) {
        ThrowInvalid(path, ToText(entries) + " entries", ToText(k) + " (the file ends)");
      }
    } while (line.empty() || line[0] == '%');
    const std::string where = path + ":" + ToText(line_no);
    double v[3];
    long long i = 0, j = 0;
    double value = 0.0;
    if (coordinate) {
      ParseNumbers(line, 3, v, where);
      i = ToIndex(v[0], rows, where) - 1;
      j = ToIndex(v[1], cols, where) - 1;
      value = v[2];
      if (symmetric && j > i) ThrowInvalid(where, "an entry of the lower triangle (row >= column)", "\"" + line + "\"");
    } else {
      ParseNumbers(line, 1, v, where);
      value = v[0];
      i = r;
      j = c;
      if (++r == rows) {
        ++c;
        r = symmetric ? c : 0;
      }
    }
    CheckFinite(value, where);
    if (value == 0.0 && !coordinate) continue;
    triplets.emplace_back(static_cast<int>(i), static_cast<int>(j), value);
    if (symmetric && i != j) triplets.emplace_back(static_cast<int>(j), static_cast<int>(i), value);
  }
  while (ReadLine(in, &line, path, ++line_no)) {
    if (!line.empty() && line[0] != '%' && line.find_first_not_of(" \t\r") != std::string::npos) {
      ThrowInvalid(path + ":" + ToText(line_no), ToText(entries) + " entries (as the size line says)",
                   "more");
    }
  }
  Eigen::SparseMatrix<double> a(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  a.setFromTriplets(triplets.begin(), triplets.end());
  return a;
}

void WriteMatrixMarket(const std::string& path, const Eigen::SparseMatrix<double>& a) {
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "%%MatrixMarket matrix coordinate real general\n"
        << a.rows() << " " << a.cols() << " " << a.nonZeros() << "\n";
    char buffer[64];
    for (int k = 0; k < a.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it) {
        std::snprintf(buffer, sizeof(buffer), "%lld %lld %.17g\n", static_cast<long long>(it.row() + 1),
                      static_cast<long long>(it.col() + 1), it.value());
        out << buffer;
      }
    }
  });
}

ImportedMatrices ReadModelMatrices(const ModelFiles& files) {
  ImportedMatrices m;
  if (!files.mat_file.empty()) {
    // The checks ReadMat makes before libmatio allocates anything (v4/v5 headers, v7.3 storage).
    internal::CheckMatStructure(files.mat_file);
    std::optional<internal::Hdf5Quiet> quiet;
    if (internal::CheckMat73Storage(files.mat_file)) quiet.emplace();
    std::unique_ptr<mat_t, int (*)(mat_t*)> mat(Mat_Open(files.mat_file.c_str(), MAT_ACC_RDONLY),
                                                Mat_Close);
    if (!mat) ThrowInvalid(files.mat_file, "a readable MATLAB .mat file", "a file libmatio cannot open");
    m.mass = FromMatVariable(mat.get(), files.mass, files.mat_file);
    m.stiffness = FromMatVariable(mat.get(), files.stiffness, files.mat_file);
    if (!files.damping.empty()) m.damping = FromMatVariable(mat.get(), files.damping, files.mat_file);
  } else {
    m.mass = ReadMatrixMarket(files.mass);
    m.stiffness = ReadMatrixMarket(files.stiffness);
    if (!files.damping.empty()) m.damping = ReadMatrixMarket(files.damping);
  }
  const Eigen::Index n = m.mass.rows();
  auto check = [&](const Eigen::SparseMatrix<double>& a, const std::string& what) {
    if (a.rows() != n || a.cols() != n) {
      ThrowInvalid(what, "a square matrix of the mass matrix's size " + ToText(n) + " x " + ToText(n),
                   ToText(a.rows()) + " x " + ToText(a.cols()));
    }
  };
  const std::string src = files.mat_file.empty() ? std::string() : files.mat_file + ": ";
  check(m.mass, src + files.mass);
  check(m.stiffness, src + files.stiffness);
  if (m.damping.size() > 0) check(m.damping, src + files.damping);
  return m;
}

}  // namespace podid
