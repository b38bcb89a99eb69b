#pragma once
// libmatio helpers shared by io_mat.cpp and io_mat_struct.cpp (not installed).

#include <matio.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "podid/core/time_series.hpp"

namespace podid::internal {

/// Mat_VarFree, and before it, with libmatio < 1.5.25 (whose Mat_VarFree
/// frees a function handle's array of cells but not the cells), the cells of
/// every function handle in the variable (found by podid_fuzz_mat; fixed in
/// matio by c60ac5c).
void FreeMatVar(matvar_t* var);
struct MatVarFreer {
  void operator()(matvar_t* var) const { FreeMatVar(var); }
};
using MatVarPtr = std::unique_ptr<matvar_t, MatVarFreer>;

/// Mat_VarRead(mat, name) (null if no variable has that name or its data
/// cannot be read), with every variable it passes over freed by FreeMatVar:
/// Mat_VarRead frees those itself, and with libmatio < 1.5.25 leaks the cells
/// of a function handle among them (podid_fuzz_mat). The first of that name.
MatVarPtr ReadMatVar(mat_t* mat, const std::string& name);

/// Elements of a variable (product of its dimensions).
std::size_t MatElements(const matvar_t& var);
/// Real, non-sparse, numeric class (double .. uint64, logical included), rank 2.
bool IsMatNumeric(const matvar_t& var);
/// "a struct", "a cell array", "a complex matrix", ... for messages.
std::string MatClassText(const matvar_t& var);
/// The data of a numeric variable read with its data, as doubles (column-major);
/// throws for non-finite values, naming `where`.
std::vector<double> MatDoubles(const matvar_t& var, const std::string& where);
/// The text of a char array (rows joined by '\n'), CleanText'ed; "" if `var`
/// is null or not a char array.
std::string MatText(const matvar_t* var);

/// The time vector of a struct or file: `t` (dim n) checked by FitUniformGrid
/// (rounding from the class: single or double precision), named `where`.
/// Returns the stamps, or the fitted grid when they are rounded.
Eigen::VectorXd MatTimeVector(const std::vector<double>& t,
                              matio_classes time_class,
                              const std::string& where);

/// The channel blocks (each samples x k, all of `samples` rows) side by side,
/// in order; each block is freed as soon as it is copied.
Eigen::MatrixXd ConcatenateChannels(std::vector<Eigen::MatrixXd>& blocks, Eigen::Index samples);

/// Interprets a struct read with its data (test-system export or plain
/// struct; io.hpp's ReadMat). `step_s` is used when it has no time (> 0);
/// `has_time` says whether it had. Appends notes.
TimeSeries MatStructSeries(matvar_t& var,
                           const std::string& path,
                           double step_s,
                           bool* has_time,
                           std::vector<std::string>* notes);

/// True when a struct's info (fields listed, no data) looks like a test-system
/// export (x_values and y_values) or a plain struct (a numeric field of >= 2
/// elements).
bool IsMatSeriesStruct(matvar_t& info);

/// ReadMat with `has_time` telling whether the file had its own time.
TimeSeries ReadMatFile(const std::string& path,
                       const std::string& variable,
                       const std::string& time_variable,
                       double step_s,
                       bool* has_time,
                       std::vector<std::string>* notes);

/// Checks, with libhdf5 and before matio reads data, that every dataset of a
/// v7.3 (HDF5) file can be stored in it: its elements <= (allocated storage +
/// 16) * the largest deflate ratio. Never-written chunks allocate nothing, so
/// a dataset declaring 3e8 doubles in a 10 kB file is rejected here. Also
/// silences HDF5's own error printing meanwhile. The sum of all datasets'
/// elements must be <= kMaxReadValues. Returns false (checks nothing) for a
/// file that is not v7.3. Throws std::invalid_argument.
bool CheckMat73Storage(const std::string& path);

/// While alive, HDF5 prints no error stack (H5Eset_auto2 off, restored after):
/// libmatio's failures become one podid message.
class Hdf5Quiet {
 public:
  Hdf5Quiet();
  ~Hdf5Quiet();
  Hdf5Quiet(const Hdf5Quiet&) = delete;
  Hdf5Quiet& operator=(const Hdf5Quiet&) = delete;

 private:
  // H5E_auto2_t and the client data, kept opaque so that hdf5.h stays out.
  int (*function_)(std::int64_t, void*) = nullptr;
  void* data_ = nullptr;
};

}  // namespace podid::internal
