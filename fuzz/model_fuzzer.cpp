// libFuzzer target: an imported model's matrices (ReadModelMatrices) from
// arbitrary bytes. The first byte chooses the form: even, three Matrix Market
// files (the rest split at the first two "\n%%" markers into M, K and C);
// odd, a .mat file holding M, K and C. Invalid input must end in
// std::invalid_argument; a result must satisfy the reader's contract.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "fuzz_support.hpp"
#include "podid/core/model_io.hpp"

namespace {

// Square matrices of one size within the bounds, finite entries.
bool SatisfiesModelContract(const podid::ImportedMatrices& m) {
  const auto n = m.mass.rows();
  auto ok = [n](const Eigen::SparseMatrix<double>& a) {
    if (a.rows() != n || a.cols() != n || a.nonZeros() > podid::kMaxImportedEntries) return false;
    for (int k = 0; k < a.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it) {
        if (!std::isfinite(it.value())) return false;
      }
    }
    return true;
  };
  return n >= 1 && n <= podid::kMaxImportedDofs && ok(m.mass) && ok(m.stiffness) &&
         (m.damping.size() == 0 || ok(m.damping));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool mat = (data[0] & 1) != 0;
  const std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
  podid::ModelFiles files;
  if (mat) {
    files.mat_file = podid::fuzz::WriteInput(data + 1, size - 1, ".mat");
    files.mass = "M";
    files.stiffness = "K";
    files.damping = "C";
  } else {
    const std::size_t first = rest.find("\n%%");
    const std::size_t second = first == rest.npos ? rest.npos : rest.find("\n%%", first + 1);
    const std::string_view m = rest.substr(0, first);
    const std::string_view k =
        first == rest.npos ? std::string_view() : rest.substr(first + 1, second - first - 1);
    const std::string_view c = second == rest.npos ? std::string_view() : rest.substr(second + 1);
    auto write = [](std::string_view text, const char* suffix) {
      return podid::fuzz::WriteInput(reinterpret_cast<const std::uint8_t*>(text.data()),
                                     text.size(), suffix);
    };
    files.mass = write(m, "-m.mtx");
    files.stiffness = write(k, "-k.mtx");
    if (!c.empty()) files.damping = write(c, "-c.mtx");
  }
  try {
    if (!SatisfiesModelContract(podid::ReadModelMatrices(files))) __builtin_trap();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
