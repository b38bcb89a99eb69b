// v7.3 .mat files (HDF5): storage checks with libhdf5 before libmatio reads,
// and HDF5's own error printing silenced while podid reads such a file.
#include <hdf5.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "io_mat_internal.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid::internal {
namespace {

/// Largest ratio of uncompressed to compressed size that deflate reaches (as
/// in io_mat.cpp); the slack covers tiny datasets and MATLAB's empty markers.
constexpr double kMaxDeflateRatio = 1032.0;
constexpr double kSlackBytes = 16.0;

bool IsMat73(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char header[128] = {};
  if (!in.read(reinterpret_cast<char*>(header), sizeof header)) return false;
  const bool little = header[126] == 'I' && header[127] == 'M';
  const bool big = header[126] == 'M' && header[127] == 'I';
  const unsigned version = little ? header[124] | header[125] << 8
                           : big  ? header[125] | header[124] << 8
                                  : 0u;
  return version == 0x0200;
}

struct VisitState {
  std::string path;
  std::string bad_name;
  double bad_elements = 0.0, bad_storage = 0.0;
  double total_elements = 0.0;
};

herr_t VisitObject(hid_t file, const char* name, const H5O_info_t* info, void* data) {
  auto* state = static_cast<VisitState*>(data);
  if (info->type != H5O_TYPE_DATASET) return 0;
  const hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
  if (dataset < 0) return 0;  // matio reports what it cannot open
  const hid_t space = H5Dget_space(dataset);
  const hssize_t points = space >= 0 ? H5Sget_simple_extent_npoints(space) : 0;
  const double storage = static_cast<double>(H5Dget_storage_size(dataset));
  if (space >= 0) H5Sclose(space);
  H5Dclose(dataset);
  const double elements = static_cast<double>(points);
  state->total_elements += elements;
  if (elements > (storage + kSlackBytes) * kMaxDeflateRatio) {
    state->bad_name = name;
    state->bad_elements = elements;
    state->bad_storage = storage;
    return 1;  // stop
  }
  return 0;
}

}  // namespace

bool CheckMat73Storage(const std::string& path) {
  if (!IsMat73(path)) return false;
  const Hdf5Quiet quiet;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) {
    ThrowInvalid(path, "a readable MATLAB v7.3 .mat file (HDF5)",
                 "a file HDF5 cannot open (truncated or corrupt)");
  }
  VisitState state;
  state.path = path;
  const herr_t status = H5Ovisit(file, H5_INDEX_NAME, H5_ITER_NATIVE, VisitObject, &state);
  H5Fclose(file);
  if (!state.bad_name.empty()) {
    ThrowInvalid(path + ": dataset '/" + state.bad_name + "'",
                 "data stored in the file (" + ToText(state.bad_storage) +
                     " bytes allocated hold at most " +
                     ToText((state.bad_storage + kSlackBytes) * kMaxDeflateRatio) + " elements)",
                 ToText(state.bad_elements) + " elements declared (chunks never written)");
  }
  if (status < 0) {
    ThrowInvalid(path, "a readable MATLAB v7.3 .mat file (HDF5)",
                 "objects HDF5 cannot list (a corrupt file)");
  }
  if (state.total_elements > static_cast<double>(kMaxReadValues)) {
    ThrowInvalid(path,
                 "at most " + std::to_string(kMaxReadValues) +
                     " values (podid's memory budget, kMaxReadValues)",
                 ToText(state.total_elements) + " declared in its datasets");
  }
  return true;
}

Hdf5Quiet::Hdf5Quiet() {
  H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Hdf5Quiet::~Hdf5Quiet() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

}  // namespace podid::internal
